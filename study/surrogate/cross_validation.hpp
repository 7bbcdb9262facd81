// K-fold cross-validation of a whole fitting procedure, its choices included
// (Hastie, Tibshirani & Friedman 2009, sec. 7.10.2): each fold is predicted by
// a model fitted afresh on the other runs, so the Q^2 sees what a
// leave-one-out error with the fitted terms held fixed cannot, such as terms
// selected to fit the very runs they are scored on.
//   Q^2_CV = 1 - sum_i (y_i - yhat_{-fold(i)}(x_i))^2 / sum_i (y_i - mean y)^2.
#pragma once

#include <functional>
#include <string>

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"

namespace rover::study {

// Folds used when there are at least this many runs; fewer runs: one fold
// per run (leave-one-out with refits).
inline constexpr int kCrossValidationFolds = 10;

struct CrossValidation {
  int folds = 0;         // 0: not done, and why_not says why
  double q2 = 0.0;       // Q^2_CV when folds > 0
  std::string why_not;   // empty when done
  std::string refits;    // what each fold fits afresh, for the reports: "terms re-selected"
};

// Fits on (x_train, y_train) and returns the predictions at x_test. Throws
// std::invalid_argument when the training runs cannot support the fit.
using FitAndPredict = std::function<Eigen::VectorXd(const DesignMatrix& x_train, const Eigen::VectorXd& y_train,
                                                    const DesignMatrix& x_test)>;

// Run r belongs to fold r mod K, K = min(kCrossValidationFolds, runs), so the
// folds are reproducible and each spans the design. Not done (why_not set)
// when a fold leaves fewer than min_training_runs to fit on, when a fit
// throws std::invalid_argument (its message is kept), or when y has no spread.
CrossValidation cross_validate(const DesignMatrix& x, const Eigen::VectorXd& y, int min_training_runs,
                               const FitAndPredict& fit_and_predict);

}  // namespace rover::study
