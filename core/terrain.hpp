// The terrain: a height field z = h(x, y) in the world frame (docs/model.md §6,
// "Terrain"; paper section 2.2.3).
//
// Either the horizontal plane z = const (the default, z = 0) or heights on a
// regular grid, interpolated bilinearly. Outside the grid (x, y) is clamped to
// the grid's extent: the edge values extend outwards and the slope across a
// clamped direction is 0.
//
// On a grid line the bilinear slope across the line jumps. Within
// kGridLineTolerance_m (1e-9 m) of a grid line the gradient component across
// that line is the mean of the two one-sided slopes (docs/model.md §6), so
// the normal does not flip with round-off at a convex edge. This holds on the
// grid boundary too, where the outer one-sided slope is the 0 of the clamped
// extension, and at grid nodes for both components at once. The height itself
// is the plain bilinear interpolant (continuous, never snapped).
//
// A Terrain is immutable after construction; the grid is shared (not copied)
// between copies, so passing a Terrain by value is cheap and using one from
// many threads is safe. height()/sample() allocate nothing and make no virtual
// calls: they are meant for the inner loop of the wheel-contact search.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

namespace rover {

// Heights on a regular grid. Node (ix, iy) lies at
// (origin_x_m + ix * spacing_x_m, origin_y_m + iy * spacing_y_m) and its height
// is heights_m[iy * nx + ix] (rows of constant y, x varying fastest).
struct HeightGrid {
  double origin_x_m = 0, origin_y_m = 0, spacing_x_m = 0, spacing_y_m = 0;
  int nx = 0, ny = 0;
  std::vector<double> heights_m;

  double node_x(int ix) const { return origin_x_m + ix * spacing_x_m; }
  double node_y(int iy) const { return origin_y_m + iy * spacing_y_m; }
  double at(int ix, int iy) const {
    return heights_m[static_cast<std::size_t>(iy) * static_cast<std::size_t>(nx) +
                     static_cast<std::size_t>(ix)];
  }
};

// Throws std::invalid_argument unless nx, ny >= 2, the spacings are positive
// and finite, the origin is finite, heights_m has nx * ny entries and all of
// them are finite.
void validate_height_grid(const HeightGrid& grid);

// Height and gradient (dh/dx, dh/dy) at one point.
struct TerrainSample {
  double height_m = 0.0;
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
};

class Terrain {
 public:
  // Distance from a grid line within which the slope across it is the mean of
  // the two one-sided slopes.
  static constexpr double kGridLineTolerance_m = 1e-9;

  Terrain() = default;  // the plane z = 0

  // The horizontal plane z = height_m.
  static Terrain flat(double height_m = 0.0);
  // Bilinear interpolation of `grid`; throws std::invalid_argument if
  // validate_height_grid() does.
  static Terrain from_grid(HeightGrid grid);

  double height(double x, double y) const;
  Eigen::Vector2d gradient(double x, double y) const;  // (dh/dx, dh/dy)
  // Unit upward normal (-dh/dx, -dh/dy, 1) / norm.
  Eigen::Vector3d normal(double x, double y) const;
  // Height and gradient in one call (cheaper than calling both).
  TerrainSample sample(double x, double y) const;

  bool is_flat() const { return grid_ == nullptr; }
  double flat_height() const { return flat_height_m_; }  // the plane's height (flat only)
  const HeightGrid* grid() const { return grid_.get(); }  // nullptr when flat
  // Bounds of h over the whole plane (the grid's extreme nodes; the plane's height).
  double max_height() const { return max_height_m_; }
  double min_height() const { return min_height_m_; }
  // An upper bound of h over the rectangle [x_min, x_max] x [y_min, y_max]
  // (exact up to the block size: the largest node of the blocks of
  // kMaxBlockNodes x kMaxBlockNodes cells it touches). Lets the contact search
  // skip rim arcs that are above the terrain nearby.
  double max_height_in(double x_min, double x_max, double y_min, double y_max) const;
  static constexpr int kMaxBlockNodes = 16;

 private:
  std::shared_ptr<const HeightGrid> grid_;
  // Block maxima for max_height_in(): block (bx, by) covers nodes
  // [bx B, bx B + B] x [by B, by B + B] (B = kMaxBlockNodes, shared edges).
  std::shared_ptr<const std::vector<double>> block_max_;
  int blocks_x_ = 0, blocks_y_ = 0;
  double flat_height_m_ = 0.0;
  double max_height_m_ = 0.0;
  double min_height_m_ = 0.0;
};

}  // namespace rover
