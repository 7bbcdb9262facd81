// Terrain height field: flat plane or bilinear height grid (see terrain.hpp;
// docs/model.md §6, "Terrain").
#include "core/terrain.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/number_text.hpp"

namespace rover {
namespace {

// Where a coordinate falls along one grid axis.
struct AxisLocation {
  // Height: the cell [cell, cell + 1] and the fraction within it, in [0, 1]
  // (the coordinate clamped to the grid's extent).
  int cell = 0;
  double frac = 0.0;
  // Where the *other* gradient component is interpolated along this axis: the
  // same as (cell, frac), except on a grid line, where it is snapped onto the
  // node so that both components are evaluated at one consistent point.
  int cross_cell = 0;
  double cross_frac = 0.0;
  // The slope across this axis' grid lines is
  // slope_weight[0] * slope(slope_cell[0]) + slope_weight[1] * slope(slope_cell[1]).
  // One cell with weight 1 inside a cell; the two neighbours with weight 1/2 on
  // a grid line (the mean rule); weight 0 for the flat clamped extension.
  int slope_cell[2] = {0, 0};
  double slope_weight[2] = {0.0, 0.0};
};

// The cell floor((coord - origin) / spacing) and the fraction within it, with
// coord clamped to the grid's extent; returns the unclamped grid coordinate.
double find_cell(double coord, double origin, double spacing, int n, int& cell, double& frac) {
  const double last = n - 1;
  const double u = (coord - origin) / spacing;
  const double clamped = u > 0.0 ? (u < last ? u : last) : 0.0;
  cell = std::min(static_cast<int>(clamped), n - 2);  // floor, as clamped >= 0; n - 2 at the upper edge
  frac = clamped - cell;
  return u;
}

AxisLocation locate(double coord, double origin, double spacing, int n) {
  AxisLocation a;
  const double last = n - 1;
  const double u = find_cell(coord, origin, spacing, n, a.cell, a.frac);
  a.cross_cell = a.cell;
  a.cross_frac = a.frac;

  const int node = static_cast<int>(a.cell + a.frac + 0.5);  // nearest node, 0..n-1
  const double offset = coord - (origin + node * spacing);
  if (std::abs(offset) <= Terrain::kGridLineTolerance_m) {
    // On the grid line through `node`: mean of the slopes of the cells on
    // either side; beyond the grid's edge the clamped extension is flat.
    a.cross_cell = std::min(node, n - 2);
    a.cross_frac = node == n - 1 ? 1.0 : 0.0;
    a.slope_cell[0] = std::max(node - 1, 0);
    a.slope_weight[0] = node >= 1 ? 0.5 : 0.0;
    a.slope_cell[1] = std::min(node, n - 2);
    a.slope_weight[1] = node <= n - 2 ? 0.5 : 0.0;
  } else if (u > 0.0 && u < last) {
    a.slope_cell[0] = a.cell;
    a.slope_weight[0] = 1.0;
  }
  // else: outside the grid, clamped; the slope across is 0.
  return a;
}

double bilinear(const HeightGrid& g, int ix, double tx, int iy, double ty) {
  const double* row0 = g.heights_m.data() + static_cast<std::size_t>(iy) * g.nx + ix;
  const double* row1 = row0 + g.nx;
  const double h0 = row0[0] + tx * (row0[1] - row0[0]);
  const double h1 = row1[0] + tx * (row1[1] - row1[0]);
  return h0 + ty * (h1 - h0);
}

// dh/dx inside column cell ix, interpolated in y at (iy, ty); times spacing_x.
double x_difference(const HeightGrid& g, int ix, int iy, double ty) {
  const double* row0 = g.heights_m.data() + static_cast<std::size_t>(iy) * g.nx + ix;
  const double* row1 = row0 + g.nx;
  return (row0[1] - row0[0]) + ty * ((row1[1] - row1[0]) - (row0[1] - row0[0]));
}

// dh/dy inside row cell iy, interpolated in x at (ix, tx); times spacing_y.
double y_difference(const HeightGrid& g, int ix, double tx, int iy) {
  const double* row0 = g.heights_m.data() + static_cast<std::size_t>(iy) * g.nx + ix;
  const double* row1 = row0 + g.nx;
  return (row1[0] - row0[0]) + tx * ((row1[1] - row0[1]) - (row1[0] - row0[0]));
}

[[noreturn]] void invalid(const std::string& problem) {
  throw std::invalid_argument("terrain height grid: " + problem);
}

}  // namespace

Terrain Terrain::flat(double height_m) {
  if (!std::isfinite(height_m))
    throw std::invalid_argument("flat terrain: height must be finite, got " +
                                number_text(height_m));
  Terrain t;
  t.flat_height_m_ = t.max_height_m_ = t.min_height_m_ = height_m;
  return t;
}

void validate_height_grid(const HeightGrid& grid) {
  if (grid.nx < 2 || grid.ny < 2)
    invalid("need at least 2 x 2 nodes, got nx = " + std::to_string(grid.nx) +
            ", ny = " + std::to_string(grid.ny));
  if (!(grid.spacing_x_m > 0.0) || !std::isfinite(grid.spacing_x_m) || !(grid.spacing_y_m > 0.0) ||
      !std::isfinite(grid.spacing_y_m))
    invalid("spacings must be positive and finite, got " + number_text(grid.spacing_x_m) +
            ", " + number_text(grid.spacing_y_m));
  if (!std::isfinite(grid.origin_x_m) || !std::isfinite(grid.origin_y_m))
    invalid("origin must be finite");
  const std::size_t expected = static_cast<std::size_t>(grid.nx) * static_cast<std::size_t>(grid.ny);
  if (grid.heights_m.size() != expected)
    invalid("expected nx * ny = " + std::to_string(grid.nx) + " * " + std::to_string(grid.ny) +
            " = " + std::to_string(expected) + " heights, got " +
            std::to_string(grid.heights_m.size()));
  for (std::size_t k = 0; k < expected; ++k)
    if (!std::isfinite(grid.heights_m[k]))
      invalid("height at node (ix " + std::to_string(k % grid.nx) + ", iy " +
              std::to_string(k / grid.nx) + ") is not finite");
}

Terrain Terrain::from_grid(HeightGrid grid) {
  validate_height_grid(grid);
  Terrain t;
  const auto [lo, hi] = std::minmax_element(grid.heights_m.begin(), grid.heights_m.end());
  t.min_height_m_ = *lo;
  t.max_height_m_ = *hi;
  t.grid_ = std::make_shared<const HeightGrid>(std::move(grid));
  // Block maxima (shared edge nodes, so every cell lies inside one block).
  const HeightGrid& g = *t.grid_;
  constexpr int B = kMaxBlockNodes;
  t.blocks_x_ = (g.nx - 2) / B + 1;
  t.blocks_y_ = (g.ny - 2) / B + 1;
  auto blocks = std::make_shared<std::vector<double>>(
      static_cast<std::size_t>(t.blocks_x_) * static_cast<std::size_t>(t.blocks_y_),
      -std::numeric_limits<double>::infinity());
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const double h = g.at(ix, iy);
      // A node on a block edge belongs to both blocks.
      for (int by = std::max(0, (iy - 1) / B); by <= std::min(t.blocks_y_ - 1, iy / B); ++by)
        for (int bx = std::max(0, (ix - 1) / B); bx <= std::min(t.blocks_x_ - 1, ix / B); ++bx) {
          double& m = (*blocks)[static_cast<std::size_t>(by) * static_cast<std::size_t>(t.blocks_x_) +
                                static_cast<std::size_t>(bx)];
          m = std::max(m, h);
        }
    }
  t.block_max_ = std::move(blocks);
  return t;
}

double Terrain::height(double x, double y) const {
  if (!grid_) return flat_height_m_;
  const HeightGrid& g = *grid_;
  if (std::isnan(x) || std::isnan(y)) return std::numeric_limits<double>::quiet_NaN();
  int ix, iy;
  double tx, ty;
  find_cell(x, g.origin_x_m, g.spacing_x_m, g.nx, ix, tx);
  find_cell(y, g.origin_y_m, g.spacing_y_m, g.ny, iy, ty);
  return bilinear(g, ix, tx, iy, ty);
}

TerrainSample Terrain::sample(double x, double y) const {
  TerrainSample s;
  if (!grid_) {
    s.height_m = flat_height_m_;
    return s;
  }
  if (std::isnan(x) || std::isnan(y)) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, {nan, nan}};
  }
  const HeightGrid& g = *grid_;
  const AxisLocation ax = locate(x, g.origin_x_m, g.spacing_x_m, g.nx);
  const AxisLocation ay = locate(y, g.origin_y_m, g.spacing_y_m, g.ny);
  s.height_m = bilinear(g, ax.cell, ax.frac, ay.cell, ay.frac);
  double dx = 0.0, dy = 0.0;
  for (int k = 0; k < 2; ++k) {
    if (ax.slope_weight[k] != 0.0)
      dx += ax.slope_weight[k] * x_difference(g, ax.slope_cell[k], ay.cross_cell, ay.cross_frac);
    if (ay.slope_weight[k] != 0.0)
      dy += ay.slope_weight[k] * y_difference(g, ax.cross_cell, ax.cross_frac, ay.slope_cell[k]);
  }
  s.gradient = {dx / g.spacing_x_m, dy / g.spacing_y_m};
  return s;
}

Eigen::Vector2d Terrain::gradient(double x, double y) const { return sample(x, y).gradient; }

Eigen::Vector3d Terrain::normal(double x, double y) const {
  const Eigen::Vector2d g = sample(x, y).gradient;
  return Eigen::Vector3d(-g.x(), -g.y(), 1.0).normalized();
}

}  // namespace rover

namespace rover {

double Terrain::max_height_in(double x_min, double x_max, double y_min, double y_max) const {
  if (!grid_) return flat_height_m_;
  const HeightGrid& g = *grid_;
  // Cells touched by the rectangle, clamped to the grid (outside, the edge values extend).
  auto cell = [](double v, double origin, double spacing, int n) {
    const double c = std::floor((v - origin) / spacing);
    return static_cast<int>(std::clamp(c, 0.0, static_cast<double>(n - 2)));
  };
  if (!(x_min <= x_max) || !(y_min <= y_max)) return max_height_m_;
  const int bx0 = cell(x_min, g.origin_x_m, g.spacing_x_m, g.nx) / kMaxBlockNodes;
  const int bx1 = cell(x_max, g.origin_x_m, g.spacing_x_m, g.nx) / kMaxBlockNodes;
  const int by0 = cell(y_min, g.origin_y_m, g.spacing_y_m, g.ny) / kMaxBlockNodes;
  const int by1 = cell(y_max, g.origin_y_m, g.spacing_y_m, g.ny) / kMaxBlockNodes;
  double m = -std::numeric_limits<double>::infinity();
  for (int by = by0; by <= by1; ++by)
    for (int bx = bx0; bx <= bx1; ++bx)
      m = std::max(m, (*block_max_)[static_cast<std::size_t>(by) * static_cast<std::size_t>(blocks_x_) +
                                    static_cast<std::size_t>(bx)]);
  return m;
}

}  // namespace rover
