// See least_squares_loo.hpp.
#include "study/surrogate/least_squares_loo.hpp"

#include <cmath>

#include <Eigen/Cholesky>

namespace rover::study {
namespace {

// A Gram matrix whose Cholesky pivot falls below this fraction of its largest
// diagonal entry is treated as singular (a basis the design cannot resolve).
constexpr double kRelativePivotFloor = 1e-12;
// Leverages this close to 1 make the LOO residual meaningless.
constexpr double kMaxLeverage = 1.0 - 1e-10;
// A column whose component orthogonal to the others is below this fraction
// of its norm is in their span (the square root of kRelativePivotFloor).
constexpr double kSpanTolerance = 1e-6;

bool cholesky_ok(const Eigen::LLT<Eigen::MatrixXd>& llt, double max_diagonal) {
  if (llt.info() != Eigen::Success) return false;
  const Eigen::VectorXd d = llt.matrixL().toDenseMatrix().diagonal();
  return d.minCoeff() * d.minCoeff() > kRelativePivotFloor * max_diagonal;
}

}  // namespace

IncrementalLeastSquares::IncrementalLeastSquares(const Eigen::VectorXd& y, double y_variance)
    : y_(y), y_variance_(y_variance), q_(y.size(), 0), r_(0, 0), r_inv_(0, 0), qty_(0) {}

bool IncrementalLeastSquares::add_column(const Eigen::VectorXd& column) {
  const Eigen::Index k = r_.cols();
  const double norm = column.norm();
  if (!(norm > 0.0) || k >= q_.rows()) return false;
  // Two passes of classical Gram-Schmidt ("twice is enough").
  Eigen::VectorXd r_col = q_.transpose() * column;
  Eigen::VectorXd v = column - q_ * r_col;
  const Eigen::VectorXd correction = q_.transpose() * v;
  v -= q_ * correction;
  r_col += correction;
  const double rho = v.norm();
  if (!(rho > kSpanTolerance * norm)) return false;
  q_.conservativeResize(Eigen::NoChange, k + 1);
  q_.col(k) = v / rho;
  r_.conservativeResize(k + 1, k + 1);
  r_.row(k).setZero();
  r_.col(k).head(k) = r_col;
  r_(k, k) = rho;
  // [R r; 0 rho]^-1 = [R^-1, -R^-1 r / rho; 0, 1 / rho].
  Eigen::VectorXd new_col = -(r_inv_ * r_col) / rho;
  r_inv_.conservativeResize(k + 1, k + 1);
  r_inv_.row(k).setZero();
  r_inv_.col(k).head(k) = new_col;
  r_inv_(k, k) = 1.0 / rho;
  qty_.conservativeResize(k + 1);
  qty_(k) = q_.col(k).dot(y_);
  return true;
}

LeastSquaresLoo IncrementalLeastSquares::fit() const {
  LeastSquaresLoo fit;
  const Eigen::Index n = q_.rows(), p = r_.cols();
  if (p == 0 || n <= p) return fit;
  const Eigen::VectorXd leverage = q_.rowwise().squaredNorm();
  if (leverage.maxCoeff() >= kMaxLeverage) return fit;
  fit.coefficients = r_inv_ * qty_;
  const Eigen::VectorXd residual = y_ - q_ * qty_;
  const double loo =
      (residual.array() / (1.0 - leverage.array())).square().sum() / static_cast<double>(n);
  fit.relative_loo = loo / y_variance_;
  const double correction =
      static_cast<double>(n) / static_cast<double>(n - p) * (1.0 + r_inv_.squaredNorm());
  fit.corrected_loo = correction * fit.relative_loo;
  fit.ok = std::isfinite(fit.corrected_loo);
  return fit;
}

bool least_squares_coefficients(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                                Eigen::VectorXd* coefficients) {
  if (psi.rows() <= psi.cols()) return false;
  const Eigen::MatrixXd gram = psi.transpose() * psi;
  const Eigen::LLT<Eigen::MatrixXd> llt(gram);
  if (!cholesky_ok(llt, gram.diagonal().maxCoeff())) return false;
  *coefficients = llt.solve(psi.transpose() * y);
  return true;
}

namespace {

// What the leave-one-out error of a fit on Psi needs of it: the Cholesky
// factor of Psi^T Psi, the leverages h_ii and the correction T(P, N) =
// N / (N - P) (1 + tr((Psi^T Psi)^-1)). ok false for N <= P, a Gram matrix
// that is not positive definite, or a leverage too close to 1.
struct LooFactor {
  bool ok = false;
  Eigen::LLT<Eigen::MatrixXd> llt;
  Eigen::VectorXd leverage;
  double correction = 0.0;
};

LooFactor loo_factor(const Eigen::MatrixXd& psi) {
  LooFactor f;
  const Eigen::Index n = psi.rows(), p = psi.cols();
  if (n <= p) return f;
  const Eigen::MatrixXd gram = psi.transpose() * psi;
  f.llt.compute(gram);
  if (!cholesky_ok(f.llt, gram.diagonal().maxCoeff())) return f;
  // W = L^-1 Psi^T: h_ii = |W_i|^2; L^-1 gives tr((Psi^T Psi)^-1) = |L^-1|_F^2.
  const Eigen::MatrixXd w = f.llt.matrixL().solve(psi.transpose());
  const Eigen::MatrixXd l_inv = f.llt.matrixL().solve(Eigen::MatrixXd::Identity(p, p));
  f.leverage = w.colwise().squaredNorm().transpose();
  if (f.leverage.maxCoeff() >= kMaxLeverage) return f;
  f.correction = static_cast<double>(n) / static_cast<double>(n - p) * (1.0 + l_inv.squaredNorm());
  f.ok = true;
  return f;
}

}  // namespace

LeastSquaresLoo least_squares_loo(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                                  double y_variance) {
  LeastSquaresLoo fit;
  const LooFactor factor = loo_factor(psi);
  if (!factor.ok) return fit;
  fit.coefficients = factor.llt.solve(psi.transpose() * y);
  const Eigen::VectorXd residual = y - psi * fit.coefficients;
  const double loo = (residual.array() / (1.0 - factor.leverage.array())).square().sum() /
                     static_cast<double>(psi.rows());
  fit.relative_loo = loo / y_variance;
  fit.corrected_loo = factor.correction * fit.relative_loo;
  fit.ok = std::isfinite(fit.corrected_loo);
  return fit;
}

MultiOutputLeastSquaresLoo least_squares_loo(const Eigen::MatrixXd& psi, const Eigen::MatrixXd& y,
                                             const Eigen::VectorXd& y_variances) {
  MultiOutputLeastSquaresLoo fit;
  const LooFactor factor = loo_factor(psi);
  if (!factor.ok) return fit;
  fit.coefficients = factor.llt.solve(psi.transpose() * y);
  const Eigen::MatrixXd scaled =
      (y - psi * fit.coefficients).array().colwise() / (1.0 - factor.leverage.array());
  const Eigen::VectorXd loo = scaled.colwise().squaredNorm().transpose() / static_cast<double>(psi.rows());
  fit.corrected_loo.resize(y.cols());
  for (Eigen::Index j = 0; j < y.cols(); ++j)
    fit.corrected_loo(j) = y_variances(j) > 0.0 ? factor.correction * loo(j) / y_variances(j) : 0.0;
  fit.ok = fit.corrected_loo.allFinite();
  return fit;
}

}  // namespace rover::study
