// See calibration_probe.hpp.
#include "study/studies/calibration_probe.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "study/runtime/rank0_broadcast.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/runtime/task_farm.hpp"
#include "study/studies/report_number.hpp"

namespace rover::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The column of delta_chi2 at t = -2 and t = +2 (the 95 % interval's ends).
constexpr Eigen::Index kColumnMinusTwo = 2, kColumnPlusTwo = 5;

// The weighted sum of squares at `values`, offsets at their profiled best;
// NaN when a run failed.
double weighted_sum_of_squares(const CalibrationStudy& s, const std::vector<double>& values,
                               const std::vector<double>& weights) {
  const CalibrationResiduals r = calibration_residuals(s, values);
  if (!r.ok) return kNaN;
  double sum = 0.0;
  for (std::size_t k = 0; k < r.residuals.size(); ++k)
    for (double e : r.residuals[k]) sum += weights[k] * weights[k] * e * e;
  return sum;
}

// The probe points: point 0 the fit, point 1 + k * 2 kProbesPerSide + j the
// j-th multiple along parameter k's direction; empty when outside the bounds.
std::vector<std::vector<double>> probe_points(const CalibrationStudy& s, const ProbeInput& in) {
  const std::vector<double> multiples = probe_multiples();
  const std::size_t p = s.fit.size();
  std::vector<std::vector<double>> points{in.values};
  for (std::size_t k = 0; k < p; ++k) {
    const auto column = static_cast<Eigen::Index>(k);
    const double variance = in.covariance(column, column);
    for (const double t : multiples) {
      std::vector<double> v = in.values;
      bool inside = std::isfinite(variance) && variance > 0.0;
      for (std::size_t i = 0; i < p && inside; ++i) {
        v[i] += t * in.covariance(static_cast<Eigen::Index>(i), column) / std::sqrt(variance);
        inside = std::isfinite(v[i]) && v[i] >= s.fit[i].lower && v[i] <= s.fit[i].upper;
      }
      points.push_back(inside ? v : std::vector<double>{});
    }
  }
  return points;
}

}  // namespace

std::vector<double> probe_multiples() {
  std::vector<double> t;
  for (std::size_t j = kProbesPerSide; j-- > 0;) t.push_back(-kProbeMultiples[j]);
  for (const double m : kProbeMultiples) t.push_back(m);
  return t;
}

ProfileProbe probe_profile_directions(const CalibrationStudy& s, const ProbeInput& in, int progress_interval_s) {
  const std::vector<std::vector<double>> points = probe_points(s, in);
  std::vector<int> tasks;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].empty()) tasks.push_back(static_cast<int>(i));
  TaskFarmOptions farm;
  farm.label = "calibrate: profile probe";
  farm.progress_interval_s = progress_interval_s;
  farm.stop = &InterruptGuard::flag();
  const std::vector<TaskResult> runs = run_task_farm(
      tasks, [&](int i) { return TaskResult{i, 0, "", {weighted_sum_of_squares(s, points[static_cast<std::size_t>(i)], in.curve_weights)}}; },
      {}, farm);
  std::vector<double> sums(points.size(), kNaN);
  for (const TaskResult& r : runs) sums[static_cast<std::size_t>(r.index)] = r.values.at(0);
  broadcast_from_rank0(sums);

  ProfileProbe probe;
  const std::size_t p = s.fit.size(), columns = 2 * kProbesPerSide;
  if (!std::isfinite(sums[0]) || !(in.noise_sd > 0.0)) {
    probe.message = "the objective at the fit could not be evaluated again";
    return probe;
  }
  const double variance = in.noise_sd * in.noise_sd;
  probe.delta_chi2.resize(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(columns));
  for (std::size_t k = 0; k < p; ++k)
    for (std::size_t j = 0; j < columns; ++j) {
      const std::size_t i = 1 + k * columns + j;
      const double delta = (sums[i] - sums[0]) / variance;  // NaN stays NaN
      probe.delta_chi2(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(j)) = delta;
      if (delta < -kLowerMargin && delta < probe.better_delta_chi2) {
        probe.better_delta_chi2 = delta;
        probe.better_values = points[i];
      }
    }
  for (std::size_t k = 0; k < p; ++k) {
    const auto row = static_cast<Eigen::Index>(k);
    // A NaN side (outside the bounds) compares false: the bound limits the interval there.
    if (probe.delta_chi2(row, kColumnMinusTwo) < kFlatDeltaChi2 || probe.delta_chi2(row, kColumnPlusTwo) < kFlatDeltaChi2)
      probe.flat.push_back(s.fit[k].name);
  }
  probe.ok = true;
  return probe;
}

std::string describe_flat_parameters(const ProfileProbe& probe, const CalibrationStudy& s) {
  std::string text;
  for (std::size_t k = 0; k < s.fit.size(); ++k) {
    const auto row = static_cast<Eigen::Index>(k);
    bool flagged = false;
    for (const std::string& name : probe.flat) flagged = flagged || name == s.fit[k].name;
    if (!flagged) continue;
    text += (text.empty() ? "" : "; ") + s.fit[k].name + ": the objective rises by " +
            format_number(probe.delta_chi2(row, kColumnMinusTwo), 3) + " and " +
            format_number(probe.delta_chi2(row, kColumnPlusTwo), 3) +
            " chi-square units at -2 and +2 standard errors (4 expected)";
  }
  return text.empty() ? text
                      : "the objective is flatter than the Gauss-Newton intervals assume (" + text +
                            "): the true interval is wider; use \"profile\": true or "
                            "--method mcmc";
}

}  // namespace rover::study
