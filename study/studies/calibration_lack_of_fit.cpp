// See calibration_lack_of_fit.hpp.
#include "study/studies/calibration_lack_of_fit.hpp"

#include <cmath>
#include <limits>

#include "study/estimators/residual_correlation.hpp"
#include "study/studies/report_number.hpp"

namespace rover::study {

std::string residual_structure_reason(const CalibrationStudy& s, const std::vector<double>& lag1) {
  std::string structured;
  for (std::size_t k = 0; k < s.datasets.size() && k < lag1.size(); ++k) {
    ResidualCorrelation c;
    c.points = s.datasets[k].t.size();
    c.lag1 = lag1[k];
    if (!c.model_leaves_structure()) continue;
    structured += std::string(structured.empty() ? "" : "; ") + s.datasets[k].path + ": lag-1 autocorrelation " +
                  format_number(c.lag1, 3) + ", independent noise stays below " +
                  format_number(c.white_noise_bound(), 2) + "; intervals too narrow by about " +
                  format_number(c.interval_narrowing(), 2) + "x";
  }
  if (structured.empty()) return "";
  return "the residuals are correlated (" + structured + "): the model does not follow the data (data of " +
         "another scenario or channel? a missing effect?) or the noise is filtered, and the intervals assume " +
         "independent noise";
}

std::string noise_contradiction_reason(const CalibrationStudy& s, const std::vector<double>& rss_m2,
                                       double known_noise_sd_m) {
  if (!(known_noise_sd_m > 0.0)) return "";
  std::string contradicted;
  for (std::size_t k = 0; k < s.datasets.size() && k < rss_m2.size(); ++k) {
    const double n = static_cast<double>(s.datasets[k].t.size());
    const double chi2 = rss_m2[k] / (known_noise_sd_m * known_noise_sd_m);
    if (!((chi2 - n) / std::sqrt(2.0 * n) > kNoiseContradictionSd)) continue;
    const double rms_m = std::sqrt(rss_m2[k] / n);
    contradicted += std::string(contradicted.empty() ? "" : "; ") + s.datasets[k].path + ": residual RMS " +
                    format_number(rms_m, 4) + " m, " + format_number(rms_m / known_noise_sd_m, 3) +
                    " times the noise sd (chi-square " + format_number(chi2, 4) + " for " +
                    format_number(n, 6) + " points)";
  }
  if (contradicted.empty()) return "";
  return "the residuals contradict mcmc.noise_sd " + format_number(known_noise_sd_m, 4) + " m (" + contradicted +
         "): the posterior is too narrow; give the data's noise sd, or sample it (leave out noise_sd)";
}

LackOfFit lack_of_fit_at(const CalibrationStudy& s, const std::vector<double>& values, double known_noise_sd_m) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  LackOfFit lack;
  const CalibrationResiduals fit = calibration_residuals(s, values);
  std::vector<double> rss_m2;
  for (std::size_t k = 0; k < s.datasets.size(); ++k) {
    if (!fit.ok) {
      lack.residual_lag1.push_back(kNaN);
      lack.residual_rms_m.push_back(kNaN);
      rss_m2.push_back(kNaN);
      continue;
    }
    double rss = 0.0;
    for (double r : fit.residuals[k]) rss += r * r;
    rss_m2.push_back(rss);
    lack.residual_rms_m.push_back(std::sqrt(rss / static_cast<double>(fit.residuals[k].size())));
    lack.residual_lag1.push_back(residual_correlation(fit.residuals[k]).lag1);
  }
  for (const std::string& why : {residual_structure_reason(s, lack.residual_lag1),
                                 noise_contradiction_reason(s, rss_m2, known_noise_sd_m)})
    if (!why.empty()) lack.reason += (lack.reason.empty() ? "" : "; ") + why;
  return lack;
}

}  // namespace rover::study
