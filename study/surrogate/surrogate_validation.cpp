// See surrogate_validation.hpp.
#include "study/surrogate/surrogate_validation.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace rover::study {
namespace {

// Growth of the design suggested when a Q^2 is too low.
constexpr int kSuggestedGrowthFactor = 2;

std::string shown_q2(double q2) {
  std::ostringstream text;
  text << std::setprecision(3) << q2;
  return text.str();
}

std::string reselected_q2_name(const CrossValidation& cv) {
  return std::to_string(cv.folds) + "-fold cross-validated Q2 (" + cv.refits + ")";
}

}  // namespace

void score_held_out(const Eigen::VectorXd& observed, const Eigen::VectorXd& predicted,
                    SurrogateValidation* validation) {
  if (observed.size() == 0 || observed.size() != predicted.size())
    throw std::invalid_argument("held-out validation: " + std::to_string(observed.size()) +
                                " observed values and " + std::to_string(predicted.size()) +
                                " predictions; they must be equal in number and at least 1");
  if (!observed.allFinite() || !predicted.allFinite())
    throw std::invalid_argument("held-out validation: non-finite observed or predicted value");
  const double sse = (observed - predicted).squaredNorm();
  const double sst = (observed.array() - observed.mean()).square().sum();
  validation->test_points = static_cast<int>(observed.size());
  validation->rmse_test = std::sqrt(sse / static_cast<double>(observed.size()));
  validation->q2_test = observed.size() >= kMinHeldOutRuns && sst > 0.0 ? 1.0 - sse / sst : std::nan("");
}

bool crowded_selection(const SurrogateValidation& v) {
  return v.selected_terms > 0 && v.training_runs < kMinRunsPerSelectedTerm * v.selected_terms;
}

std::string surrogate_not_to_trust(const std::string& output_name, const SurrogateValidation& v) {
  const bool held_out_q2_defined = v.test_points > 0 && std::isfinite(v.q2_test);
  std::string q2;
  bool below_zero = false;
  const auto below_floor = [&](const std::string& which, double value) {
    if (!(value < v.q2_threshold)) return;
    q2 += (q2.empty() ? "" : ", ") + which + " " + shown_q2(value);
    below_zero = below_zero || value < 0.0;
  };
  below_floor("leave-one-out Q2", v.q2_loo);
  if (v.reselected.folds > 0) below_floor(reselected_q2_name(v.reselected), v.reselected.q2);
  if (held_out_q2_defined) below_floor("held-out Q2", v.q2_test);
  if (!q2.empty())
    return "the surrogate of '" + output_name + "' " +
           (below_zero ? "predicts worse than the mean of its runs (" + q2 + " < 0)"
                       : "falls short of q2_threshold (" + q2 + " < " + shown_q2(v.q2_threshold) + ")") +
           ": its predictions and indices are not to be trusted";
  const bool not_done = v.reselected.folds == 0 && !v.reselected.why_not.empty();
  const bool not_recorded = v.reselected.folds == 0 && v.reselected.why_not.empty() && crowded_selection(v);
  if (held_out_q2_defined || !(not_done || not_recorded)) return "";
  const int runs_wanted = crowded_selection(v) ? kMinRunsPerSelectedTerm * v.selected_terms : v.training_runs + 1;
  const std::string fitted = v.selected_terms > 0 ? std::to_string(v.selected_terms) + " terms selected on " : "fitted on ";
  return "the surrogate of '" + output_name + "' (" + fitted + std::to_string(v.training_runs) + " runs) " +
         (not_done ? "cannot be cross-validated (" + v.reselected.why_not + ")"
                   : std::string("records no cross-validation")) +
         ": its leave-one-out Q2 " + shown_q2(v.q2_loo) +
         " alone cannot be taken at its word (it keeps what was fitted to those runs), and its predictions and "
         "indices are not to be trusted; give at least " + std::to_string(runs_wanted) + " runs, or held-out runs";
}

std::string reselected_q2_text(const SurrogateValidation& v) {
  if (v.reselected.folds == 0) return "";
  std::ostringstream text;
  text << std::fixed << std::setprecision(4) << v.reselected.q2;
  return ", " + reselected_q2_name(v.reselected) + " " + text.str();
}

std::string held_out_q2_undefined_reason(const SurrogateValidation& v) {
  if (v.test_points == 0 || std::isfinite(v.q2_test)) return "";
  if (v.test_points < kMinHeldOutRuns)
    return "Q2 needs at least " + std::to_string(kMinHeldOutRuns) + " held-out runs, got " +
           std::to_string(v.test_points);
  return "the " + std::to_string(v.test_points) + " held-out values are equal: no spread to explain";
}

void flag_low_q2(const std::string& output_name, int runs, double threshold,
                 SurrogateValidation* validation) {
  std::ostringstream text;
  validation->q2_threshold = threshold;
  const bool loo_low = validation->q2_loo < threshold;
  const CrossValidation& cv = validation->reselected;
  const bool cv_low = cv.folds > 0 && cv.q2 < threshold;
  const bool test_low = validation->test_points > 0 && validation->q2_test < threshold;
  if (!loo_low && !cv_low && !test_low) {
    validation->warning.clear();
    return;
  }
  text << "surrogate of '" << output_name << "' is not accurate enough:";
  if (loo_low) text << " leave-one-out Q2 " << validation->q2_loo;
  if (cv_low) text << (loo_low ? "," : "") << " " << reselected_q2_name(cv) << " " << cv.q2;
  if (test_low)
    text << (loo_low || cv_low ? "," : "") << " held-out Q2 " << validation->q2_test << " on "
         << validation->test_points << " runs";
  text << " < " << threshold << " from " << runs << " runs; try a larger N (e.g. "
       << kSuggestedGrowthFactor * runs << " runs)";
  validation->warning = text.str();
}

}  // namespace rover::study
