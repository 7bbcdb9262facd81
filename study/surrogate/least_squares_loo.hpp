// Ordinary least squares with its leave-one-out error in closed form.
//
// With the hat matrix H = Psi (Psi^T Psi)^-1 Psi^T, the leave-one-out residual
// of run i is (y_i - yhat_i) / (1 - h_ii), so no refits are needed (Allen
// 1974). The relative LOO error eps = mean(((y - yhat) / (1 - h))^2) / Var(y)
// is corrected for the optimism of small designs by the factor of Chapelle,
// Vapnik & Bengio (2002) as used by Blatman & Sudret (2011):
//   T(P, N) = N / (N - P) (1 + tr(C_emp^-1) / N),   C_emp = Psi^T Psi / N,
// where tr(C_emp^-1) / N = tr((Psi^T Psi)^-1).
#pragma once

#include <Eigen/Core>

namespace rover::study {

struct LeastSquaresLoo {
  bool ok = false;                // false: N <= P or Psi^T Psi not positive definite
  Eigen::VectorXd coefficients;   // P
  double relative_loo = 0.0;      // eps_LOO, uncorrected
  double corrected_loo = 0.0;     // T(P, N) eps_LOO
};

// y_variance: the variance the errors are relative to (the caller's output
// variance, > 0). Needs Psi.rows() == y.size().
LeastSquaresLoo least_squares_loo(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                                  double y_variance);

// The same for several outputs on one basis (one column of y per output),
// factoring Psi once. y_variances: one per output; an output with variance 0
// gets corrected_loo 0 when fitted exactly.
struct MultiOutputLeastSquaresLoo {
  bool ok = false;
  Eigen::MatrixXd coefficients;     // P x outputs
  Eigen::VectorXd corrected_loo;    // one per output
};
MultiOutputLeastSquaresLoo least_squares_loo(const Eigen::MatrixXd& psi, const Eigen::MatrixXd& y,
                                             const Eigen::VectorXd& y_variances);

// Least squares on a growing set of columns, for following a LARS path: the
// thin QR factorisation Psi_A = Q R is extended one column at a time by
// Gram-Schmidt with one reorthogonalisation (Giraud, Langou & Rozloznik 2005),
// R^-1 alongside it, so that each added column costs O(N k + k^2) instead of
// a fresh O(N k^2) factorisation. Leverages h_i = |Q_i|^2 and
// tr((Psi^T Psi)^-1) = |R^-1|_F^2 give the same corrected LOO error as
// least_squares_loo.
class IncrementalLeastSquares {
 public:
  IncrementalLeastSquares(const Eigen::VectorXd& y, double y_variance);
  // Appends a column; false (and nothing changes) if it is numerically in the
  // span of the columns already there.
  bool add_column(const Eigen::VectorXd& column);
  int columns() const { return static_cast<int>(r_.cols()); }
  // The fit on the columns so far; ok false without columns, with N <= k or
  // with a leverage of 1 (as least_squares_loo).
  LeastSquaresLoo fit() const;

 private:
  Eigen::VectorXd y_;
  double y_variance_;
  Eigen::MatrixXd q_;      // N x k, orthonormal columns
  Eigen::MatrixXd r_;      // k x k upper triangular
  Eigen::MatrixXd r_inv_;  // its inverse
  Eigen::VectorXd qty_;    // Q^T y
};

// The coefficients alone (no LOO); ok false as above.
bool least_squares_coefficients(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                                Eigen::VectorXd* coefficients);

}  // namespace rover::study
