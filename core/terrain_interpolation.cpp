// Thin-plate spline interpolation of terrain control points onto a grid (see
// terrain_interpolation.hpp; docs/model.md §6, "Terrain").
#include "core/terrain_interpolation.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "core/number_text.hpp"

namespace rover {
namespace {

// phi(r) = r^2 log r, written in r^2 to avoid a square root.
double thin_plate_kernel(double r2) { return r2 > 0.0 ? 0.5 * r2 * std::log(r2) : 0.0; }

[[noreturn]] void invalid(const std::string& problem) {
  throw std::invalid_argument("terrain control points: " + problem);
}

std::string point_text(const Eigen::Vector3d& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.10g, %.10g, %.10g)", p.x(), p.y(), p.z());
  return text;
}

}  // namespace

ThinPlateSpline::ThinPlateSpline(const std::vector<Eigen::Vector3d>& points) {
  const Eigen::Index n = static_cast<Eigen::Index>(points.size());
  if (n < 3) invalid("need at least 3 points, got " + std::to_string(n));
  for (Eigen::Index i = 0; i < n; ++i)
    if (!points[i].allFinite()) invalid("point " + std::to_string(i) + " is not finite");

  // Centre and scale to unit size: the spline is invariant under this, and the
  // system is far better conditioned.
  centre_.setZero();
  for (const auto& p : points) centre_ += p.head<2>();
  centre_ /= static_cast<double>(n);
  scale_ = 0.0;
  for (const auto& p : points) scale_ = std::max(scale_, (p.head<2>() - centre_).norm());
  if (!(scale_ > 0.0)) invalid("all points have the same (x, y)");
  centres_.resize(2, n);
  Eigen::VectorXd z(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    centres_.col(i) = (points[i].head<2>() - centre_) / scale_;
    z(i) = points[i].z();
  }

  // Distinct points (relative tolerance) ...
  constexpr double kCoincident = 1e-9;
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j)
      if ((centres_.col(i) - centres_.col(j)).norm() <= kCoincident)
        invalid("points " + std::to_string(i) + " " + point_text(points[i]) + " and " +
                std::to_string(j) + " " + point_text(points[j]) + " have the same (x, y)");
  // ... not all on one line (the plane through them would not be unique).
  const Eigen::Matrix2d scatter = centres_ * centres_.transpose();
  const Eigen::Vector2d spread = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvalues();
  if (!(spread(0) > 1e-18 * spread(1))) invalid("all points lie on one line");

  Eigen::MatrixXd kernel(n, n);
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = j; i < n; ++i)
      kernel(i, j) = kernel(j, i) =
          thin_plate_kernel((centres_.col(i) - centres_.col(j)).squaredNorm());
  Eigen::MatrixXd affine_basis(n, 3);
  affine_basis.col(0).setOnes();
  affine_basis.rightCols(2) = centres_.transpose();

  // Q^T K Q and Q^T z; the weights live in the span of Q2 (P^T w = 0).
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(affine_basis);
  const auto q = qr.householderQ();
  kernel.applyOnTheLeft(q.adjoint());
  kernel.applyOnTheRight(q);
  const Eigen::VectorXd qz = q.adjoint() * z;
  const Eigen::Index m = n - 3;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(m);
  if (m > 0) {
    const Eigen::LLT<Eigen::MatrixXd> llt(kernel.bottomRightCorner(m, m));
    if (llt.info() != Eigen::Success)
      invalid("the interpolation system is singular (points nearly coincide)");
    g = llt.solve(qz.tail(m));
  }
  Eigen::VectorXd qw = Eigen::VectorXd::Zero(n);
  qw.tail(m) = g;
  weights_ = q * qw;
  // R a = Q1^T (z - K w) = (Q^T z)_1 - (Q^T K Q)_12 g.
  const Eigen::Vector3d rhs = qz.head<3>() - kernel.topRightCorner(3, m) * g;
  affine_ = qr.matrixQR().topLeftCorner<3, 3>().triangularView<Eigen::Upper>().solve(rhs);

  // Guard against an ill-conditioned solve: the spline must pass through the points.
  const double z_scale = std::max(1.0, z.cwiseAbs().maxCoeff());
  for (Eigen::Index i = 0; i < n; ++i) {
    const double miss = std::abs((*this)(points[i].x(), points[i].y()) - z(i));
    if (!(miss <= 1e-8 * z_scale))
      invalid("the interpolation system is ill-conditioned (misses point " + std::to_string(i) +
              " by " + number_text(miss) + "; points nearly coincide?)");
  }
}

double ThinPlateSpline::operator()(double x, double y) const {
  const Eigen::Vector2d p = (Eigen::Vector2d(x, y) - centre_) / scale_;
  double h = affine_(0) + affine_(1) * p.x() + affine_(2) * p.y();
  for (Eigen::Index i = 0; i < centres_.cols(); ++i)
    h += weights_(i) * thin_plate_kernel((centres_.col(i) - p).squaredNorm());
  return h;
}

HeightGrid grid_from_control_points(const std::vector<Eigen::Vector3d>& points,
                                    const GridGeometry& geometry) {
  if (geometry.nx < 2 || geometry.ny < 2)
    invalid("grid needs at least 2 x 2 nodes, got " + std::to_string(geometry.nx) + " x " +
            std::to_string(geometry.ny));
  if (!(geometry.spacing_x_m > 0.0) || !(geometry.spacing_y_m > 0.0) ||
      !std::isfinite(geometry.spacing_x_m) || !std::isfinite(geometry.spacing_y_m))
    invalid("grid spacings must be positive and finite");
  if (!std::isfinite(geometry.origin_x_m) || !std::isfinite(geometry.origin_y_m))
    invalid("grid origin must be finite");
  const ThinPlateSpline spline(points);
  HeightGrid grid = grid_with_heights(
      geometry, std::vector<double>(static_cast<std::size_t>(geometry.nx) * static_cast<std::size_t>(geometry.ny)));
  for (int iy = 0; iy < grid.ny; ++iy)
    for (int ix = 0; ix < grid.nx; ++ix)
      grid.heights_m[static_cast<std::size_t>(iy) * grid.nx + ix] =
          spline(grid.node_x(ix), grid.node_y(iy));
  return grid;
}

}  // namespace rover
