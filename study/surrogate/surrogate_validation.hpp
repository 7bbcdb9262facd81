// Validation of a surrogate model: the leave-one-out Q^2 it was fitted with,
// Q^2 and RMSE on held-out runs when there are some, and a warning when a Q^2
// falls below the accepted threshold.
//   Q^2 = 1 - sum (y - yhat)^2 / sum (y - mean y)^2   (the predictivity coefficient).
#pragma once

#include <string>

#include <Eigen/Core>

#include "study/surrogate/cross_validation.hpp"

namespace rover::study {

// Q^2 below this flags a warning unless the caller chooses another threshold.
inline constexpr double kDefaultQ2Threshold = 0.95;
// A held-out Q^2 compares the prediction errors with the spread of the
// held-out values: it needs two values at least.
inline constexpr int kMinHeldOutRuns = 2;
// A fit whose terms were selected on its own runs needs at least this many
// runs per selected term for its leave-one-out Q^2 to mean anything: with
// about as many terms as runs, the selection itself interpolates the runs and
// leave-one-out (which keeps the terms fixed) cannot see it.
inline constexpr int kMinRunsPerSelectedTerm = 2;
// A surrogate whose Q^2 (leave-one-out, cross-validated or held-out) is
// below this leaves more than half of the output's variance unexplained:
// every Sobol' index, a share of that variance, can then be off by more than
// a half, and its predictions are not to be trusted.
inline constexpr double kMinTrustedQ2 = 0.5;

struct SurrogateValidation {
  double q2_loo = 0.0;  // 1 - relative (corrected, for PCE) LOO error
  int test_points = 0;  // held-out runs validated on; 0: q2_test, rmse_test unset
  double q2_test = 0.0;  // NaN: undefined (held_out_q2_undefined_reason)
  double rmse_test = 0.0;
  std::string warning;  // empty when every Q^2 reaches the threshold
  // Terms selected on the training runs (polynomial chaos); 0 for a model
  // without selected terms (Gaussian process).
  int selected_terms = 0;
  int training_runs = 0;
  // The cross-validation of the whole fit, terms re-selected in every fold
  // (folds 0 when it was not done: why_not says why when it could not be).
  CrossValidation reselected;
};

// Whether the fit selected so many terms for its runs that its leave-one-out
// Q^2 cannot be taken at its word.
bool crowded_selection(const SurrogateValidation& v);


// Q^2 and RMSE of predictions against held-out values. Throws
// std::invalid_argument if the sizes differ, are empty or hold non-finite values.
// Q^2 of fewer than kMinHeldOutRuns values, or of equal values (no spread to
// explain), is undefined: NaN (the RMSE is set).
void score_held_out(const Eigen::VectorXd& observed, const Eigen::VectorXd& predicted,
                    SurrogateValidation* validation);

// Why the surrogate is not to be trusted, naming `output_name`; "" when it
// is. Either a Q^2 it has (leave-one-out, re-selected cross-validated, or a
// defined held-out one) is below kMinTrustedQ2, so it leaves most of the
// variance unexplained or predicts worse than the mean (below 0), or, with no
// held-out Q^2 defined, its selection could not be cross-validated (too few
// runs to refit a fold on: why_not set). Such a surrogate, and indices from
// it, are results not to be trusted.
std::string surrogate_not_to_trust(const std::string& output_name, const SurrogateValidation& v);

// ", <K>-fold cross-validated Q2 (terms re-selected) <q2>" when that
// cross-validation was done, else "": for the reports beside the Q2_LOO.
std::string reselected_q2_text(const SurrogateValidation& v);

// Why the held-out Q^2 is undefined ("" when it is defined or there are no
// held-out runs).
std::string held_out_q2_undefined_reason(const SurrogateValidation& v);

// Sets validation->warning (or clears it) from q2_loo, the re-selected
// cross-validated Q^2 when done and, if test_points > 0 and it is defined,
// q2_test: names the output, the Q^2, the threshold and the number of runs,
// and suggests a larger N.
void flag_low_q2(const std::string& output_name, int runs, double threshold,
                 SurrogateValidation* validation);

}  // namespace rover::study
