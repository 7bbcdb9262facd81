// Basis selection by least-angle regression (LARS; Efron, Hastie, Johnstone &
// Tibshirani 2004) and the hybrid LARS of Blatman & Sudret (2011): LARS only
// orders the candidate terms by when they enter the active set; each active
// set along the path is refitted by ordinary least squares and the one with
// the smallest corrected leave-one-out error (least_squares_loo.hpp) is kept.
//
// The constant term (column 0) is always in the model; LARS runs on the other
// columns centred and scaled to unit norm, and on the centred output.
#pragma once

#include <atomic>
#include <vector>

#include <Eigen/Core>

namespace rover::study {

// The LARS path, followed one entering column at a time so that a caller can
// stop early. The Cholesky factor of the active columns' Gram matrix is
// extended at each entry, so a step costs O(N P + N k + k^2) for k active
// columns.
class LarsPath {
 public:
  LarsPath(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y);
  // The next column of psi (1 .. P-1) to enter the active set, or -1 when the
  // path has ended (correlations vanished, or the active columns collinear).
  int next();

 private:
  Eigen::MatrixXd x_;        // centred, unit-norm candidate columns (psi columns 1 ..)
  Eigen::VectorXd yc_, mu_;  // centred output, current fit
  Eigen::VectorXd c_;        // correlations x_^T (yc_ - mu_), updated along the path
  std::vector<int> active_;
  Eigen::MatrixXd xa_;       // the active columns, in order of entry
  Eigen::MatrixXd gram_l_;   // lower Cholesky factor of xa_^T xa_, extended per entry
  std::vector<bool> usable_; // not active and not a constant column
  int entering_ = -1;        // the column found by the last step
  double c_max_ = 0.0;       // the first (largest) correlation
  bool ended_ = false;

  bool extend_gram(int column);
  bool step();
};

// The order in which the columns 1 .. P-1 of psi enter the LARS active set,
// at most max_steps of them.
std::vector<int> lars_entry_order(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                                  int max_steps);

struct SparseSelection {
  bool ok = false;                // false: not even the constant could be fitted
  std::vector<int> columns;       // selected columns of psi, column 0 first
  Eigen::VectorXd coefficients;   // OLS coefficients on those columns
  double corrected_loo = 0.0;     // relative corrected LOO error of the selection
};

// Hybrid LARS on psi (runs x P) for y. y_variance > 0: the variance the errors
// are relative to. Stops following the path once the error has not improved
// for a number of steps (see the .cpp), or at N - 2 active terms.
// `stop`, when set, is read at every step: once true, WorkStopped is thrown
// (study/estimators/work_stopped.hpp).
SparseSelection hybrid_lars(const Eigen::MatrixXd& psi, const Eigen::VectorXd& y,
                            double y_variance, const std::atomic<bool>* stop = nullptr);

}  // namespace rover::study
