// Validation of a surrogate model: the leave-one-out Q^2 it was fitted with,
// Q^2 and RMSE on held-out runs when there are some, and a warning when a Q^2
// falls below the accepted threshold.
//   Q^2 = 1 - sum (y - yhat)^2 / sum (y - mean y)^2   (the predictivity coefficient).
#pragma once

#include <string>

#include <Eigen/Core>

namespace rover::study {

// Q^2 below this flags a warning unless the caller chooses another threshold.
inline constexpr double kDefaultQ2Threshold = 0.95;
// A held-out Q^2 compares the prediction errors with the spread of the
// held-out values: it needs two values at least.
inline constexpr int kMinHeldOutRuns = 2;

struct SurrogateValidation {
  double q2_loo = 0.0;  // 1 - relative (corrected, for PCE) LOO error
  int test_points = 0;  // held-out runs validated on; 0: q2_test, rmse_test unset
  double q2_test = 0.0;  // NaN: undefined (held_out_q2_undefined_reason)
  double rmse_test = 0.0;
  std::string warning;  // empty when every Q^2 reaches the threshold
};

// Q^2 and RMSE of predictions against held-out values. Throws
// std::invalid_argument if the sizes differ, are empty or hold non-finite values.
// Q^2 of fewer than kMinHeldOutRuns values, or of equal values (no spread to
// explain), is undefined: NaN (the RMSE is set).
void score_held_out(const Eigen::VectorXd& observed, const Eigen::VectorXd& predicted,
                    SurrogateValidation* validation);

// Why the surrogate predicts worse than the mean of the values it is scored
// on (a leave-one-out or defined held-out Q^2 below 0), naming `output_name`
// and the Q^2; "" when it does not. Such a surrogate, and indices from it,
// are results not to be trusted.
std::string worse_than_the_mean(const std::string& output_name, const SurrogateValidation& v);

// Why the held-out Q^2 is undefined ("" when it is defined or there are no
// held-out runs).
std::string held_out_q2_undefined_reason(const SurrogateValidation& v);

// Sets validation->warning (or clears it) from q2_loo and, if test_points > 0
// and it is defined, q2_test: names the output, the Q^2, the threshold and the number of runs,
// and suggests a larger N.
void flag_low_q2(const std::string& output_name, int runs, double threshold,
                 SurrogateValidation* validation);

}  // namespace rover::study
