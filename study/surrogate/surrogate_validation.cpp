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

std::string worse_than_the_mean(const std::string& output_name, const SurrogateValidation& v) {
  const auto shown = [](double q2) {
    std::ostringstream text;
    text << std::setprecision(3) << q2;
    return text.str();
  };
  std::string q2;
  if (v.q2_loo < 0.0) q2 = "leave-one-out Q2 " + shown(v.q2_loo);
  if (v.test_points > 0 && std::isfinite(v.q2_test) && v.q2_test < 0.0)
    q2 += (q2.empty() ? "" : ", ") + std::string("held-out Q2 ") + shown(v.q2_test);
  if (q2.empty()) return "";
  return "the surrogate of '" + output_name + "' predicts worse than the mean of its runs (" + q2 +
         " < 0): its predictions and indices are not to be trusted";
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
  const bool loo_low = validation->q2_loo < threshold;
  const bool test_low = validation->test_points > 0 && validation->q2_test < threshold;
  if (!loo_low && !test_low) {
    validation->warning.clear();
    return;
  }
  text << "surrogate of '" << output_name << "' is not accurate enough:";
  if (loo_low) text << " leave-one-out Q2 " << validation->q2_loo;
  if (test_low)
    text << (loo_low ? "," : "") << " held-out Q2 " << validation->q2_test << " on "
         << validation->test_points << " runs";
  text << " < " << threshold << " from " << runs << " runs; try a larger N (e.g. "
       << kSuggestedGrowthFactor * runs << " runs)";
  validation->warning = text.str();
}

}  // namespace rover::study
