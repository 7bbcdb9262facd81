// Terrain from scattered control points (docs/model.md §6, "Terrain"; paper
// section 2.2.3: "a set of control points ... interpolated on the
// bi-dimensional grid").
//
// Method: the thin-plate spline
//   h(x) = a0 + a1 x + a2 y + sum_i w_i phi(|x - x_i|),  phi(r) = r^2 log r,
// with sum_i w_i = sum_i w_i x_i = sum_i w_i y_i = 0. It passes exactly
// through every control point, minimises the bending energy
// integral(h_xx^2 + 2 h_xy^2 + h_yy^2) among all such surfaces (so it is smooth
// and does not overshoot like a high-order polynomial), and reproduces any
// plane exactly (the affine part). It exists and is unique when the points are
// distinct and not all on one line.
//
// Solve: coordinates are first centred and scaled to unit size (the spline is
// invariant under this). With P = [1 x y] (n x 3) = Q [R; 0] (Householder QR)
// and Q = [Q1 Q2], the weights are w = Q2 g where (Q2^T K Q2) g = Q2^T z,
// K_ij = phi(|x_i - x_j|). Q2^T K Q2 is positive definite for distinct,
// non-collinear points (phi is conditionally positive definite of order 2), so
// a Cholesky factorisation solves it and also detects (near-)singular input.
// Then R a = Q1^T (z - K w). Cost: the fit is O(n^3) (0.7 s for 2000 points),
// each evaluation O(n) (a 501 x 501 grid from 2000 points: 5 s). A one-off
// preprocessing step: the simulation only ever sees the resulting grid.
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/terrain.hpp"

namespace rover {

// Where the interpolated heights go: node (ix, iy) at
// (origin_x_m + ix * spacing_x_m, origin_y_m + iy * spacing_y_m).
struct GridGeometry {
  double origin_x_m = 0, origin_y_m = 0, spacing_x_m = 0, spacing_y_m = 0;
  int nx = 0, ny = 0;
};

// The height grid of `geometry` with node heights `heights_m` (row-major in y).
inline HeightGrid grid_with_heights(const GridGeometry& geometry, std::vector<double> heights_m) {
  HeightGrid grid;
  grid.origin_x_m = geometry.origin_x_m;
  grid.origin_y_m = geometry.origin_y_m;
  grid.spacing_x_m = geometry.spacing_x_m;
  grid.spacing_y_m = geometry.spacing_y_m;
  grid.nx = geometry.nx;
  grid.ny = geometry.ny;
  grid.heights_m = std::move(heights_m);
  return grid;
}

class ThinPlateSpline {
 public:
  // Fits the spline through `points` (x, y, z). Throws std::invalid_argument
  // for fewer than 3 points, non-finite values, coincident points or points
  // all on one line (the interpolant would not be unique).
  explicit ThinPlateSpline(const std::vector<Eigen::Vector3d>& points);

  double operator()(double x, double y) const;

 private:
  Eigen::Matrix2Xd centres_;   // control points in scaled coordinates
  Eigen::VectorXd weights_;    // w_i
  Eigen::Vector3d affine_;     // a0, a1, a2 in scaled coordinates
  Eigen::Vector2d centre_;     // scaled = (x - centre) / scale
  double scale_ = 1.0;
};

// Heights at the nodes of `geometry` from the thin-plate spline through
// `points`. Throws std::invalid_argument as ThinPlateSpline does, and for a
// geometry with fewer than 2 x 2 nodes or a non-positive spacing.
HeightGrid grid_from_control_points(const std::vector<Eigen::Vector3d>& points,
                                    const GridGeometry& geometry);

}  // namespace rover
