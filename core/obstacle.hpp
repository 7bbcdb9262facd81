// The trapezoid obstacle of the obstacle-negotiation scenario (docs/model.md
// section 7; paper section 3) as a height grid for the terrain (docs/model.md
// section 6).
//
// Profile along x: 0 before the foot x_f, a ramp rising at ramp_angle up to
// height H over L = H / tan(ramp_angle) (0.2747 m by default), a flat top of
// top_length, a ramp falling over L, then 0. Laterally the obstacle spans
// y in [y_min, y_max] with vertical sides, 0 outside.
//
// Grid: nodes lie exactly on x = x_f and on y = y_min, y = y_max (docs/model.md:
// "1 mm spacing with nodes on its edges"), so the foot and the lateral sides
// are rounded over at most one spacing by the bilinear interpolation, and the
// top-of-ramp edges (in general between nodes) over one spacing as well. Nodes
// on the lateral side lines take the obstacle height (closed interval). The
// grid covers the obstacle plus a margin of zero-height nodes on every side,
// so the clamped extension outside the grid is the ground z = 0.
#pragma once

#include <numbers>

#include "core/terrain.hpp"

namespace rover {

struct TrapezoidObstacle {
  double foot_x_m = 1.36;        // x of the foot of the rising ramp
  double height_m = 0.10;
  double ramp_angle_rad = 20.0 * std::numbers::pi / 180.0;
  double top_length_m = 0.30;
  double y_min_m = -0.3215;      // lateral extent (vertical sides)
  double y_max_m = -0.1215;

  double ramp_length_m() const;  // height / tan(ramp_angle)
  double far_foot_x_m() const;   // x where the falling ramp reaches the ground
  // The exact (unrounded) profile: height at (x, y), the sides included.
  double height_at(double x, double y) const;
};

// The obstacle on a grid of `spacing_m` (x and nominal y) spacing with a
// zero margin of at least `margin_m` (and at least two nodes) on every side.
// The y spacing is (y_max - y_min) / round((y_max - y_min) / spacing_m), so
// that nodes fall on both lateral sides (equal to spacing_m for the default
// obstacle). Heights are rounded to whole picometres (1e-12 m), which keeps
// the JSON file compact and is far below any physical scale.
// Throws std::invalid_argument for non-positive or non-finite parameters,
// a ramp angle outside (0, 90 deg), or y_max <= y_min.
HeightGrid trapezoid_obstacle_grid(const TrapezoidObstacle& obstacle, double spacing_m = 0.001,
                                   double margin_m = 0.005);

}  // namespace rover
