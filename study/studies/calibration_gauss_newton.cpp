// The Gauss-Newton uncertainty at a calibration optimum (Bates & Watts 1988,
// section 2.3; calibration_checked_fit.hpp).
#include "study/studies/calibration_checked_fit.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "study/runtime/rank0_broadcast.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/runtime/task_farm.hpp"
#include "study/studies/report_number.hpp"

#include "study/studies/calibration_fit.hpp"

namespace rover::study {

// The Gauss-Newton uncertainty at the optimum (values, then offsets), over
// the fitted parameters (natural units) and the profiled offsets. Collective
// (the Jacobian's runs); the result is rank 0's.
GaussNewtonResult gauss_newton_at_optimum(const CalibrationStudy& s, std::vector<double> best,
                                          const StudyRunOptions& control) {
  broadcast_from_rank0(best);
  const std::size_t p = s.fit.size(), K = s.datasets.size();
  const std::vector<double> values(best.begin(), best.begin() + static_cast<std::ptrdiff_t>(p));
  const std::vector<double> offsets(best.begin() + static_cast<std::ptrdiff_t>(p), best.end());
  const CalibrationJacobian j = calibration_jacobian(s, values, offsets, control.progress_interval_s);
  GaussNewtonResult out;
  if (world_rank() != 0) return out;
  if (!j.ok) {
    out.message = j.message + ": no intervals";
    return out;
  }
  const auto n = static_cast<std::size_t>(j.residuals.size());
  const auto q = static_cast<std::size_t>(j.jacobian.cols());
  if (n <= q) {
    out.message = "only " + std::to_string(n) + " data points for " + std::to_string(q) + " parameters: no intervals";
    return out;
  }
  // Each curve's residuals weighted by 1 / s_k (its RMS at the optimum), so
  // curves of different noise levels count by their information.
  Eigen::VectorXd residuals = j.residuals;
  out.weighted_jacobian = j.jacobian;
  std::size_t row = 0;
  for (std::size_t k = 0; k < K; ++k) {
    const auto rows = static_cast<Eigen::Index>(s.datasets[k].t.size());
    const auto first = static_cast<Eigen::Index>(row);
    out.noise_rms.push_back(std::sqrt(j.residuals.segment(first, rows).squaredNorm() / static_cast<double>(rows)));
    out.weights.push_back(K == 1 || out.noise_rms[k] == 0 ? 1.0 : 1.0 / out.noise_rms[k]);
    residuals.segment(first, rows) *= out.weights[k];
    out.weighted_jacobian.middleRows(first, rows) *= out.weights[k];
    row += s.datasets[k].t.size();
  }
  Eigen::VectorXd theta(static_cast<Eigen::Index>(q));
  for (std::size_t k = 0; k < p; ++k) theta[static_cast<Eigen::Index>(k)] = values[k];
  for (const auto& f : s.fit) out.names.push_back(f.name);
  if (!s.offset_fitted())
    for (std::size_t k = 0; k < K; ++k) {
      out.names.push_back(K == 1 ? "time_offset" : "time_offset[" + std::to_string(k) + "]");
      theta[static_cast<Eigen::Index>(p + k)] = offsets[k];
    }
  out.uncertainty = gauss_newton_uncertainty(theta, residuals, out.weighted_jacobian, 0.95, out.names);
  // The noise sd of each curve: for one curve s itself; for several, each
  // curve's RMS scaled like s (by sqrt(N / (N - q)) through the weighted fit).
  for (std::size_t k = 0; k < K; ++k)
    out.noise_sd.push_back(K == 1 ? out.uncertainty.noise_sd : out.noise_rms[k] * out.uncertainty.noise_sd);
  out.ok = true;
  return out;
}

}  // namespace rover::study
