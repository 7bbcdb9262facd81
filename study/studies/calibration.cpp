// See calibration.hpp.
#include "study/studies/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_real_distribution.hpp>
#include <Eigen/Core>
#include <nlopt.hpp>

#include "core/metrics.hpp"
#include "core/simulate.hpp"
#include "io/checkpoint.hpp"
#include "io/csv.hpp"
#include "io/hdf5_file.hpp"
#include "io/plot.hpp"
#include "study/studies/calibration_mcmc.hpp"
#include "study/runtime/rank0_broadcast.hpp"
#include "study/studies/calibration_fit.hpp"
#include "study/studies/calibration_checked_fit.hpp"
#include "study/studies/calibration_fit_flaw.hpp"
#include "study/studies/calibration_probe.hpp"
#include "study/studies/report_number.hpp"
#include "study/model/distribution_json.hpp"
#include "study/estimators/least_squares_uncertainty.hpp"
#include "study/estimators/residual_correlation.hpp"
#include "study/studies/calibration_lack_of_fit.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::study {
namespace {

// Each curve at the best fit, in data time, and the pooled RMS against the data.
void fitted_curves(const CalibrationStudy& s, CalibrationFitResult& r) {
  double rss = 0.0;
  std::size_t points = 0;
  for (std::size_t k = 0; k < s.datasets.size(); ++k) {
    CalibrationCurve curve = simulate_calibration_curve(r.checked.study, k, r.checked.fit.values);
    if (!curve.ok) {  // no curve, no RMS: fit_failed_curves() says so
      r.fitted_curves.push_back(std::move(curve));
      r.curve_rms_m.push_back(std::numeric_limits<double>::quiet_NaN());
      r.curve_residual_lag1.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    for (double& t : curve.t_s) t += r.checked.fit.offsets[k];
    const std::vector<double> residuals = shifted_residuals(curve.t_s, curve.z_m, s.datasets[k].t, s.datasets[k].z, 0.0);
    double curve_rss = 0.0;
    for (double v : residuals) curve_rss += v * v;
    rss += curve_rss;
    points += s.datasets[k].t.size();
    r.curve_rms_m.push_back(std::sqrt(curve_rss / static_cast<double>(s.datasets[k].t.size())));
    r.curve_residual_lag1.push_back(residual_correlation(residuals).lag1);
    r.fitted_curves.push_back(std::move(curve));
  }
  r.best_rms_m = points > 0 ? std::sqrt(rss / static_cast<double>(points)) : std::numeric_limits<double>::quiet_NaN();
}

// Rank 0: the curves whose run at the best fit failed, with the data file,
// the scenario and the run's message; empty when every curve ran.
std::string fit_failed_curves(const CalibrationStudy& s, const CalibrationFitResult& r) {
  std::string failed;
  for (std::size_t k = 0; k < s.datasets.size() && k < r.fitted_curves.size(); ++k) {
    if (r.fitted_curves[k].ok) continue;
    failed += std::string(failed.empty() ? "" : "; ") + "curve " + std::to_string(k + 1) + " (" + s.datasets[k].path +
              " on " + s.datasets[k].scenario_path + "): " + r.fitted_curves[k].message;
  }
  return failed.empty() ? "" : "the run of the best fit failed for " + failed + "; the best RMS is of the other curves";
}

// Rank 0: why the best fit does not describe the data at all, or empty: its
// RMS against a measured curve exceeds that curve's span, so the model never
// comes near it. A curve in millimetres, or of another channel, does that; the
// intervals of such a fit say nothing.
std::string fit_misses_the_data(const CalibrationStudy& s, const CalibrationFitResult& r) {
  std::string missed;  // each curve the fit misses by more than its own span
  for (std::size_t k = 0; k < s.datasets.size(); ++k) {
    const CalibrationDataset& d = s.datasets[k];
    const auto [low, high] = std::minmax_element(d.z.begin(), d.z.end());
    if (k < r.curve_rms_m.size() && r.curve_rms_m[k] > *high - *low)
      missed += std::string(missed.empty() ? "" : ", ") + d.path + " by " + format_number(r.curve_rms_m[k], 4) +
                " m RMS against its " + format_number(*high - *low, 4) + " m span";
  }
  if (missed.empty()) return "";
  return "the best fit misses the data (" + missed + "): are the heights in metres (not millimetres), and " +
         "of the channel named in the study?";
}

}  // namespace

CalibrationFitResult run_calibration_fit(const CalibrationStudy& s, const StudyRunOptions& control,
                                         const std::string& results_path) {
  CalibrationFitResult r;
  std::vector<double> start = s.initial_values();
  if (s.algorithm != kLeastSquaresAlgorithm) {
    start = nlopt_search(s, control, results_path, r.history);
    start.resize(s.fit.size());
    broadcast_from_rank0(start);
  }
  r.checked = checked_fit(s, start, control, r.history);
  std::vector<double> best = r.checked.fit.values;
  best.insert(best.end(), r.checked.fit.offsets.begin(), r.checked.fit.offsets.end());
  if (s.profile) r.profiles = profile_parameters(r.checked.study, r.checked.gn, best, control);
  r.not_valid_because = world_rank() == 0 ? checked_fit_flaw(r.checked) : "";
  std::vector<double> trusted{r.not_valid_because.empty() ? 1.0 : 0.0};  // rank 0 holds the intervals
  broadcast_from_rank0(trusted);
  r.trusted = trusted[0] != 0.0;
  if (world_rank() == 0) {
    fitted_curves(s, r);
    for (const std::string& flaw : {residual_structure_reason(s, r.curve_residual_lag1), fit_misses_the_data(s, r), fit_failed_curves(s, r)}) {
      if (flaw.empty()) continue;
      r.not_valid_because = flaw + (r.not_valid_because.empty() ? "" : "; " + r.not_valid_because);
      r.trusted = false;
    }
  }
  return r;
}

CalibrationEstimate estimate_calibration(const CalibrationStudy& s, const StudyRunOptions& control,
                                         const std::string& results_path) {
  CalibrationStudy without_profiles = s;  // the ranking needs the fit and its verdict, not the profiles
  without_profiles.profile = false;
  const CalibrationFitResult fit = run_calibration_fit(without_profiles, control, results_path);
  const CheckedFit& checked = fit.checked;
  CalibrationEstimate e{checked.study, checked.fit.values, checked.fit.offsets, false, "", fit.trusted,
                        fit.not_valid_because, {}, {}, {}, 0.0};
  std::vector<double> valid{0.0};
  if (!checked.fit.converged) {
    e.why_not = "the fit did not converge: " + checked.fit.message;
  } else if (world_rank() == 0 && !checked.gn.ok) {
    e.why_not = checked.gn.message;
  } else if (world_rank() == 0) {
    valid[0] = 1.0;
    e.names = checked.gn.names;
    e.weighted_jacobian = checked.gn.weighted_jacobian;
    e.weights = checked.gn.weights;
    e.noise_sd = checked.gn.uncertainty.noise_sd;
  }
  broadcast_from_rank0(valid);
  e.valid = valid[0] != 0.0;
  if (!e.valid && e.why_not.empty()) e.why_not = "the fit has no intervals";
  return e;
}

std::string describe_integrator(const IntegratorSettings& i) {
  if (i.method == IntegratorMethod::kRungeKutta4)
    return std::string(integrator_name(i.method)) + " with fixed step " + format_number(i.fixed_step_s, 3) +
           " s (no error control)";
  std::string text = std::string(integrator_name(i.method)) + " at rtol " + format_number(i.relative_tolerance, 3) +
                     ", atol " + format_number(i.absolute_tolerance, 3);
  // The slip tolerance only where a stiff method runs at another than its default.
  if (i.method != IntegratorMethod::kDormandPrince45 &&
      i.slip_tolerance != default_integrator_settings(i.method).slip_tolerance)
    text += ", slip_tol " + format_number(i.slip_tolerance, 3);
  return text;
}


}  // namespace rover::study
