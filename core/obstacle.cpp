// Trapezoid obstacle height grid (see obstacle.hpp; docs/model.md §7).
#include "core/obstacle.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "core/number_text.hpp"

namespace rover {
namespace {

void require(bool ok, const std::string& problem) {
  if (!ok) throw std::invalid_argument("trapezoid obstacle: " + problem);
}

// Height at distance s past the foot (either side of the top), unrounded.
double profile(const TrapezoidObstacle& o, double s) {
  const double rise = std::min(s, o.far_foot_x_m() - o.foot_x_m - s) * std::tan(o.ramp_angle_rad);
  return std::clamp(rise, 0.0, o.height_m);
}

}  // namespace

double TrapezoidObstacle::ramp_length_m() const { return height_m / std::tan(ramp_angle_rad); }

double TrapezoidObstacle::far_foot_x_m() const {
  return foot_x_m + 2.0 * ramp_length_m() + top_length_m;
}

double TrapezoidObstacle::height_at(double x, double y) const {
  if (!(y >= y_min_m && y <= y_max_m)) return 0.0;
  return profile(*this, x - foot_x_m);
}

HeightGrid trapezoid_obstacle_grid(const TrapezoidObstacle& o, double spacing_m, double margin_m) {
  require(std::isfinite(o.foot_x_m), "foot_x_m must be finite");
  require(o.height_m > 0.0 && std::isfinite(o.height_m), "height_m must be positive");
  require(o.ramp_angle_rad > 0.0 && o.ramp_angle_rad < std::numbers::pi / 2,
          "ramp_angle_rad must lie in (0, pi/2), got " + number_text(o.ramp_angle_rad));
  require(o.top_length_m >= 0.0 && std::isfinite(o.top_length_m),
          "top_length_m must not be negative");
  require(std::isfinite(o.y_min_m) && std::isfinite(o.y_max_m) && o.y_max_m > o.y_min_m,
          "need y_min_m < y_max_m");
  require(spacing_m > 0.0 && std::isfinite(spacing_m), "spacing must be positive");
  require(margin_m >= 0.0 && std::isfinite(margin_m), "margin must not be negative");

  // Node counts: `margin` zero nodes before the foot, the obstacle, `margin` after;
  // laterally `width` cells between the two sides.
  const double margin_cells = std::max(2.0, std::ceil(margin_m / spacing_m - 1e-9));
  const double length_cells = std::ceil((o.far_foot_x_m() - o.foot_x_m) / spacing_m - 1e-9);
  const double width_cells = std::max(1.0, std::round((o.y_max_m - o.y_min_m) / spacing_m));
  require((2.0 * margin_cells + length_cells + 1.0) * (2.0 * margin_cells + width_cells + 1.0) <= 1e8,
          "grid too large (over 1e8 nodes); use a coarser spacing or a smaller margin");
  const int margin = static_cast<int>(margin_cells);
  const int length = static_cast<int>(length_cells);
  const int width = static_cast<int>(width_cells);

  HeightGrid grid;
  grid.spacing_x_m = spacing_m;
  grid.spacing_y_m = (o.y_max_m - o.y_min_m) / width;
  grid.origin_x_m = o.foot_x_m - margin * grid.spacing_x_m;
  grid.origin_y_m = o.y_min_m - margin * grid.spacing_y_m;
  grid.nx = margin + length + margin + 1;
  grid.ny = margin + width + margin + 1;
  grid.heights_m.assign(static_cast<std::size_t>(grid.nx) * static_cast<std::size_t>(grid.ny), 0.0);

  // One row of the profile (node ix lies (ix - margin) spacings past the foot),
  // rounded to whole picometres; it fills every row between the sides, which
  // are nodes margin and margin + width (closed interval).
  std::vector<double> row(static_cast<std::size_t>(grid.nx));
  for (int ix = 0; ix < grid.nx; ++ix)
    row[ix] = std::round(profile(o, (ix - margin) * spacing_m) * 1e12) / 1e12;
  for (int iy = margin; iy <= margin + width; ++iy)
    std::copy(row.begin(), row.end(),
              grid.heights_m.begin() + static_cast<std::ptrdiff_t>(iy) * grid.nx);
  return grid;
}

}  // namespace rover
