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

bool cholesky_ok(const Eigen::LLT<Eigen::MatrixXd>& llt, double max_diagonal) {
  if (llt.info() != Eigen::Success) return false;
  const Eigen::VectorXd d = llt.matrixL().toDenseMatrix().diagonal();
  return d.minCoeff() * d.minCoeff() > kRelativePivotFloor * max_diagonal;
}

}  // namespace

bool least_squares_coefficients(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                                Eigen::VectorXd* coefficients) {
  if (psi.rows() <= psi.cols()) return false;
  const Eigen::MatrixXd gram = psi.transpose() * psi;
  const Eigen::LLT<Eigen::MatrixXd> llt(gram);
  if (!cholesky_ok(llt, gram.diagonal().maxCoeff())) return false;
  *coefficients = llt.solve(psi.transpose() * y);
  return true;
}

LeastSquaresLoo least_squares_loo(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                                  double y_variance) {
  LeastSquaresLoo fit;
  const Eigen::Index n = psi.rows(), p = psi.cols();
  if (n <= p) return fit;
  const Eigen::MatrixXd gram = psi.transpose() * psi;
  const Eigen::LLT<Eigen::MatrixXd> llt(gram);
  if (!cholesky_ok(llt, gram.diagonal().maxCoeff())) return fit;
  fit.coefficients = llt.solve(psi.transpose() * y);
  // W = L^-1 Psi^T: h_ii = |W_i|^2; L^-1 gives tr((Psi^T Psi)^-1) = |L^-1|_F^2.
  const Eigen::MatrixXd w = llt.matrixL().solve(psi.transpose());
  const Eigen::MatrixXd l_inv = llt.matrixL().solve(Eigen::MatrixXd::Identity(p, p));
  const Eigen::VectorXd leverage = w.colwise().squaredNorm().transpose();
  if (leverage.maxCoeff() >= kMaxLeverage) return fit;
  const Eigen::VectorXd residual = y - psi * fit.coefficients;
  const double loo =
      (residual.array() / (1.0 - leverage.array())).square().sum() / static_cast<double>(n);
  fit.relative_loo = loo / y_variance;
  const double correction =
      static_cast<double>(n) / static_cast<double>(n - p) * (1.0 + l_inv.squaredNorm());
  fit.corrected_loo = correction * fit.relative_loo;
  fit.ok = std::isfinite(fit.corrected_loo);
  return fit;
}

MultiOutputLeastSquaresLoo least_squares_loo(const Eigen::MatrixXd& psi, const Eigen::MatrixXd& y,
                                             const Eigen::VectorXd& y_variances) {
  MultiOutputLeastSquaresLoo fit;
  const Eigen::Index n = psi.rows(), p = psi.cols();
  if (n <= p) return fit;
  const Eigen::MatrixXd gram = psi.transpose() * psi;
  const Eigen::LLT<Eigen::MatrixXd> llt(gram);
  if (!cholesky_ok(llt, gram.diagonal().maxCoeff())) return fit;
  fit.coefficients = llt.solve(psi.transpose() * y);
  const Eigen::MatrixXd w = llt.matrixL().solve(psi.transpose());
  const Eigen::MatrixXd l_inv = llt.matrixL().solve(Eigen::MatrixXd::Identity(p, p));
  const Eigen::VectorXd leverage = w.colwise().squaredNorm().transpose();
  if (leverage.maxCoeff() >= kMaxLeverage) return fit;
  const double correction =
      static_cast<double>(n) / static_cast<double>(n - p) * (1.0 + l_inv.squaredNorm());
  const Eigen::MatrixXd scaled =
      (y - psi * fit.coefficients).array().colwise() / (1.0 - leverage.array());
  const Eigen::VectorXd loo = scaled.colwise().squaredNorm().transpose() / static_cast<double>(n);
  fit.corrected_loo.resize(y.cols());
  for (Eigen::Index j = 0; j < y.cols(); ++j)
    fit.corrected_loo(j) = y_variances(j) > 0.0 ? correction * loo(j) / y_variances(j) : 0.0;
  fit.ok = fit.corrected_loo.allFinite();
  return fit;
}

}  // namespace rover::study
