// The checked calibration fit: Levenberg-Marquardt, its intervals, the
// integration check and the profile probe (calibration_checked_fit.hpp).
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

namespace rover::study {

namespace {

// The integration check tightens the tolerances by this factor, or by its
// square when the shift exceeds kFarShiftFactor times the limit.
constexpr double kTighteningFactor = 10.0;
constexpr double kFarShiftFactor = 10.0;
// Below this rtol the stiff methods' steps collapse (a step-size underflow
// at the first impact): the check moves on to the reference integrator.
constexpr double kTightestStiffRelativeTolerance = 1e-9;

bool is_reference(const CalibrationStudy& s) {
  const IntegratorSettings& r = s.integration_check.reference;
  return s.integrator.method == r.method && s.integrator.relative_tolerance <= r.relative_tolerance &&
         s.integrator.absolute_tolerance <= r.absolute_tolerance;
}

// The integration check of a converged fit (rank 0): whether to refit, and
// the largest shift, for every rank.
struct ShiftVerdict {
  bool refit = false;
  double largest_se = 0.0;
};
ShiftVerdict check_integration(CheckedFit& c) {
  std::vector<double> verdict{0.0, 0.0};
  // Each fit is checked on its own integrator: an earlier round's shift is not this one's.
  c.shift = IntegrationShift{};
  if (world_rank() == 0 && is_reference(c.study))
    c.shift.message = "the fit runs on the reference integrator (" + describe_integrator(c.study.integrator) +
                      ") itself: there is no tighter one to check it against";
  if (world_rank() == 0 && c.fit.converged && c.gn.ok && !is_reference(c.study)) {
    c.shift = integration_shift(c.study, c.fit.values, c.fit.offsets, c.gn.weights, c.gn.weighted_jacobian,
                                c.gn.uncertainty.standard_error);
    verdict[0] = !c.shift.ok || c.shift.largest_se > c.study.integration_check.max_shift_se ? 1.0 : 0.0;
    verdict[1] = c.shift.ok ? c.shift.largest_se : 0.0;
  }
  broadcast_from_rank0(verdict);
  return {verdict[0] != 0.0, verdict[1]};
}

// The integrator after `tightenings` rounds that found the shift `largest_se`.
IntegratorSettings tightened(const CalibrationStudy& s, int tightenings, double largest_se) {
  IntegratorSettings next = s.integrator;
  // Dormand-Prince is the reference's own method; rk4 has no tolerances, only its fixed step.
  if (tightenings >= s.integration_check.max_tightenings || next.method == IntegratorMethod::kDormandPrince45 ||
      next.method == IntegratorMethod::kRungeKutta4)
    return s.integration_check.reference;
  // Tenfold, or a hundredfold when the shift is ten times the limit.
  const bool far = largest_se > kFarShiftFactor * s.integration_check.max_shift_se;
  const double factor = far ? kTighteningFactor * kTighteningFactor : kTighteningFactor;
  next.relative_tolerance /= factor;
  next.absolute_tolerance /= factor;
  if (next.relative_tolerance < kTightestStiffRelativeTolerance) return s.integration_check.reference;
  return next;
}

}  // namespace

// The probe's input, rank 0's, on every rank (the probe is collective).
ProbeInput probe_input_on_every_rank(const CheckedFit& c) {
  const std::size_t p = c.study.fit.size(), K = c.study.datasets.size();
  std::vector<double> packed;  // values, covariance (column-major), weights, noise sd
  if (world_rank() == 0) {
    packed = c.fit.values;
    const Eigen::MatrixXd covariance = c.gn.uncertainty.covariance.topLeftCorner(p, p);
    packed.insert(packed.end(), covariance.data(), covariance.data() + covariance.size());
    packed.insert(packed.end(), c.gn.weights.begin(), c.gn.weights.end());
    packed.push_back(c.gn.uncertainty.noise_sd);
  }
  broadcast_from_rank0(packed);
  ProbeInput in;
  auto at = packed.begin();
  in.values.assign(at, at + static_cast<std::ptrdiff_t>(p));
  in.covariance = Eigen::Map<const Eigen::MatrixXd>(packed.data() + p, static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(p));
  at += static_cast<std::ptrdiff_t>(p + p * p);
  in.curve_weights.assign(at, at + static_cast<std::ptrdiff_t>(K));
  in.noise_sd = packed.back();
  return in;
}

// Whether the fit and its intervals exist on rank 0, for every rank.
bool fit_has_intervals(const CheckedFit& c) {
  std::vector<double> ok{world_rank() == 0 && c.fit.converged && c.gn.ok ? 1.0 : 0.0};
  broadcast_from_rank0(ok);
  return ok[0] != 0.0;
}

CheckedFit checked_fit(const CalibrationStudy& study, std::vector<double> start, const StudyRunOptions& control,
                       FitHistory& history) {
  CheckedFit c{study, {}, {}, {}, {}, {}};
  for (int tightenings = 0, restarts = 0;;) {
    c.fit = least_squares_calibration(c.study, start, control.progress_interval_s);
    append_history(c.fit, history);
    std::vector<double> best = c.fit.values;
    best.insert(best.end(), c.fit.offsets.begin(), c.fit.offsets.end());
    c.gn = gauss_newton_at_optimum(c.study, best, control);
    std::vector<double> stop{InterruptGuard::flag().load() ? 1.0 : 0.0};  // rank 0's signal, for every rank
    broadcast_from_rank0(stop);
    if (stop[0] != 0.0) throw StudyInterrupted("interrupted during the fit; nothing was written");
    const ShiftVerdict verdict = check_integration(c);
    if (verdict.refit) {
      const IntegratorSettings next = tightened(c.study, tightenings++, verdict.largest_se);
      c.integrator_actions.push_back("the integration error moved a parameter by " +
                                     format_number(verdict.largest_se, 3) + " standard errors with " +
                                     describe_integrator(c.study.integrator) + "; refitting with " +
                                     describe_integrator(next));
      // The next fit starts where the reference's optimum is predicted to be.
      start = c.fit.values;
      for (std::size_t k = 0; k < start.size() && c.shift.ok; ++k)
        start[k] = std::clamp(start[k] + c.shift.step[k], c.study.fit[k].lower, c.study.fit[k].upper);
      broadcast_from_rank0(start);
      c.study = c.study.with_integrator(next);
      continue;
    }
    if (!fit_has_intervals(c)) return c;
    c.probe = probe_profile_directions(c.study, probe_input_on_every_rank(c), control.progress_interval_s);
    if (c.probe.better_values.empty() || restarts >= kMaxProbeRestarts) return c;
    ++restarts;
    c.integrator_actions.push_back("a point " + format_number(-c.probe.better_delta_chi2, 3) +
                                   " chi-square units below the fit lies along a profile direction; refitting "
                                   "from there");
    start = c.probe.better_values;
  }
}

}  // namespace rover::study
