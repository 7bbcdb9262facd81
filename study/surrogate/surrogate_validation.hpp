// Validation of a surrogate model: the leave-one-out Q^2 it was fitted with,
// for a polynomial chaos also the Q^2 of a cross-validation that re-selects
// its terms, Q^2 and RMSE on held-out runs when there are some, a warning
// when a Q^2 falls below the accepted threshold, and whether the surrogate is
// to be trusted at all.
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
// A fit with fewer runs than this per selected term is crowded: its
// selection can interpolate the runs, which leave-one-out (keeping the terms
// fixed) cannot see. A crowded model saved without the cross-validation that
// re-selects its terms is not trusted, and advice asks for this many runs.
inline constexpr int kMinRunsPerSelectedTerm = 2;

struct SurrogateValidation {
  double q2_loo = 0.0;  // 1 - relative (corrected, for PCE) LOO error
  int test_points = 0;  // held-out runs validated on; 0: q2_test, rmse_test unset
  double q2_test = 0.0;  // NaN: undefined (held_out_q2_undefined_reason)
  double rmse_test = 0.0;
  std::string warning;  // empty when every Q^2 reaches the threshold
  // The Q^2 every score must reach for the surrogate to be trusted (set by
  // flag_low_q2): a Sobol' index is a share of the variance, so one from a
  // surrogate that leaves a share 1 - Q^2 unexplained can be off by as much.
  double q2_threshold = kDefaultQ2Threshold;
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
// defined held-out one) is below v.q2_threshold (below 0: it predicts worse
// than the mean), or, with no
// held-out Q^2 defined, its selection could not be cross-validated (too few
// runs to refit a fold on: why_not set) or, crowded, was saved without that
// cross-validation. Such a surrogate, and indices from it, are results not to
// be trusted.
std::string surrogate_not_to_trust(const std::string& output_name, const SurrogateValidation& v);

// ", <K>-fold cross-validated Q2 (terms re-selected) <q2>" when that
// cross-validation was done, else "": for the reports beside the Q2_LOO.
std::string reselected_q2_text(const SurrogateValidation& v);

// Why the held-out Q^2 is undefined ("" when it is defined or there are no
// held-out runs).
std::string held_out_q2_undefined_reason(const SurrogateValidation& v);

// Sets validation->q2_threshold, and validation->warning (or clears it) from
// q2_loo, the re-selected
// cross-validated Q^2 when done and, if test_points > 0 and it is defined,
// q2_test: names the output, the Q^2, the threshold and the number of runs,
// and suggests a larger N.
void flag_low_q2(const std::string& output_name, int runs, double threshold,
                 SurrogateValidation* validation);

}  // namespace rover::study
