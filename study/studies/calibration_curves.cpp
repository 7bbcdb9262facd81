// A calibration's simulated curves against the measured ones: the simulated
// channel at fitted values, the residuals at a time offset and the offset
// that fits best (study/studies/calibration.hpp; docs/model.md §8 for the
// channels).
#include "study/studies/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "core/metrics.hpp"
#include "core/simulate.hpp"

namespace rover::study {

std::vector<double> shifted_residuals(const std::vector<double>& t, const std::vector<double>& z,
                                      const std::vector<double>& t_d, const std::vector<double>& z_d,
                                      double offset) {
  std::vector<double> r(t_d.size());
  for (std::size_t i = 0; i < t_d.size(); ++i) r[i] = interpolate(t, z, t_d[i] - offset) - z_d[i];
  return r;
}

double shifted_rms(const std::vector<double>& t, const std::vector<double>& z,
                   const std::vector<double>& t_d, const std::vector<double>& z_d, double offset) {
  double sum = 0.0;
  for (std::size_t i = 0; i < t_d.size(); ++i) {
    const double d = interpolate(t, z, t_d[i] - offset) - z_d[i];
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(t_d.size()));
}

// The offset scan's step, its cap (the calibration's bounds keep the range
// to a few data spans), and the golden-section polish's tolerance and cap
// (each step shrinks the bracket by 0.618: 200 reach 1e-7 s from 1e34 s).
constexpr double kOffsetScanStep_s = 1e-3;
constexpr double kMaxOffsetScanSteps = 1e8;
constexpr double kOffsetTolerance_s = 1e-7;
constexpr int kMaxGoldenSteps = 200;

double best_offset(const std::vector<double>& t, const std::vector<double>& z,
                   const std::vector<double>& t_d, const std::vector<double>& z_d, double lo,
                   double hi) {
  const int n = static_cast<int>(std::clamp(std::ceil((hi - lo) / kOffsetScanStep_s), 2.0, kMaxOffsetScanSteps));
  double best = lo, best_rms = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i) {
    const double o = std::min(hi, lo + (hi - lo) * i / n);  // lo + (hi - lo) may round above hi
    const double r = shifted_rms(t, z, t_d, z_d, o);
    if (r < best_rms) {
      best_rms = r;
      best = o;
    }
  }
  // Golden-section polish within one scan step either side.
  double a = std::max(lo, best - (hi - lo) / n), b = std::min(hi, best + (hi - lo) / n);
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = shifted_rms(t, z, t_d, z_d, c), fd = shifted_rms(t, z, t_d, z_d, d);
  for (int i = 0; i < kMaxGoldenSteps && b - a > kOffsetTolerance_s; ++i) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = shifted_rms(t, z, t_d, z_d, c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = shifted_rms(t, z, t_d, z_d, d);
    }
  }
  const double polished = 0.5 * (a + b);
  return shifted_rms(t, z, t_d, z_d, polished) <= best_rms ? polished : best;
}

CalibrationCurve simulate_calibration_curve(const CalibrationStudy& s, std::size_t dataset,
                                            const std::vector<double>& values) {
  const CalibrationDataset& d = s.datasets.at(dataset);
  CalibrationCurve curve;
  RunRecord failure;
  const std::vector<double> inputs = s.simulated_values(values);
  const std::optional<Trajectory> tr = d.model->simulate_at(inputs.data(), &failure);
  if (!tr) {
    curve.message = failure.message;
  } else if (!tr->ok() || tr->t.size() < 2) {
    curve.message = "simulation failed (" + std::string(status_name(tr->status)) + "): " + tr->message;
  } else {
    curve.ok = true;
    curve.t_s = tr->t;
    curve.z_m = channel_values(*tr, calibration_channel(d.channel).channel);
  }
  return curve;
}

double offset_for(const CalibrationStudy& s, std::size_t dataset, const CalibrationCurve& curve,
                  const std::vector<double>& values) {
  for (std::size_t k = 0; k < s.fit.size(); ++k)
    if (s.fit[k].name == "time_offset") return values[k];
  const CalibrationDataset& d = s.datasets.at(dataset);
  return best_offset(curve.t_s, curve.z_m, d.t, d.z, s.offset_min_s, s.offset_max_s);
}

CalibrationResiduals calibration_residuals(const CalibrationStudy& s, const std::vector<double>& values) {
  CalibrationResiduals out;
  for (std::size_t k = 0; k < s.datasets.size(); ++k) {
    const CalibrationCurve curve = simulate_calibration_curve(s, k, values);
    if (!curve.ok) {
      out.message = curve.message;
      return out;
    }
    const CalibrationDataset& d = s.datasets[k];
    out.offsets.push_back(offset_for(s, k, curve, values));
    out.residuals.push_back(shifted_residuals(curve.t_s, curve.z_m, d.t, d.z, out.offsets.back()));
  }
  out.ok = true;
  return out;
}

}  // namespace rover::study
