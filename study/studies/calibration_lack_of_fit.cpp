// See calibration_lack_of_fit.hpp.
#include "study/studies/calibration_lack_of_fit.hpp"

#include <cmath>
#include <limits>

#include <boost/math/distributions/chi_squared.hpp>

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

namespace {

// The curves whose residuals lie far above (`above`) or far below the noise
// sd, in words; empty when none does.
std::string contradicting_curves(const CalibrationStudy& s, const std::vector<double>& rss_m2, double noise_sd_m,
                                 bool above) {
  std::string curves;
  for (std::size_t k = 0; k < s.datasets.size() && k < rss_m2.size(); ++k) {
    const double n = static_cast<double>(s.datasets[k].t.size());
    const double chi2 = rss_m2[k] / (noise_sd_m * noise_sd_m);
    if (!std::isfinite(chi2) || n < 1.0) continue;
    const boost::math::chi_squared_distribution<double> law(n);
    const double tail = above ? boost::math::cdf(boost::math::complement(law, chi2)) : boost::math::cdf(law, chi2);
    if (!(tail < kNoiseContradictionTail)) continue;
    const double rms_m = std::sqrt(rss_m2[k] / n);
    curves += std::string(curves.empty() ? "" : "; ") + s.datasets[k].path + ": residual RMS " +
              format_number(rms_m, 4) + " m, " + format_number(rms_m / noise_sd_m, 3) +
              " times the noise sd (chi-square " + format_number(chi2, 4) + " for " + format_number(n, 6) +
              " points)";
  }
  return curves;
}

}  // namespace

std::string noise_contradiction_reason(const CalibrationStudy& s, const std::vector<double>& rss_m2,
                                       double known_noise_sd_m) {
  if (!(known_noise_sd_m > 0.0)) return "";
  const std::string given = "mcmc.noise_sd " + format_number(known_noise_sd_m, 4) + " m";
  std::string why;
  if (const std::string above = contradicting_curves(s, rss_m2, known_noise_sd_m, true); !above.empty())
    why = "the residuals contradict " + given + " (" + above + "): the posterior is too narrow";
  if (const std::string below = contradicting_curves(s, rss_m2, known_noise_sd_m, false); !below.empty())
    why += std::string(why.empty() ? "" : "; ") + "the residuals contradict " + given + " from below (" + below +
           "): the noise sd is far above the residuals' scatter, so the posterior is too wide";
  if (why.empty()) return "";
  return why + "; give the data's noise sd, or sample it (leave out noise_sd)";
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
