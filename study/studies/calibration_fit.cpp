// See calibration_fit.hpp.
#include "study/studies/calibration_fit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <Eigen/QR>

#include "study/estimators/least_squares_uncertainty.hpp"
#include "study/runtime/rank0_broadcast.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/runtime/task_farm.hpp"

namespace rover::study {
namespace {

constexpr double kLn10 = 2.302585092994046;
// Rounds of reweighting for several curves, and the relative change of every
// weight below which they have settled.
constexpr int kMaxWeightRounds = 6;
constexpr double kWeightTolerance = 1e-3;
// Least-squares stopping rules (relative step, gradient, decrease). The step
// is in internal coordinates (log10 for log-scale parameters, seconds for
// offsets): 1e-5 is far below any standard error the data give.
constexpr double kStepTolerance = 1e-5;
constexpr double kGradientTolerance = 1e-8;
constexpr double kDecreaseTolerance = 1e-9;

// Rows of each curve in the stacked residual vector.
std::vector<std::size_t> first_rows(const CalibrationStudy& s) {
  std::vector<std::size_t> first(s.datasets.size() + 1, 0);
  for (std::size_t k = 0; k < s.datasets.size(); ++k) first[k + 1] = first[k] + s.datasets[k].t.size();
  return first;
}

// The column of curve k's offset: the fitted time_offset, else p + k.
std::size_t offset_column(const CalibrationStudy& s, std::size_t k) {
  for (std::size_t c = 0; c < s.fit.size(); ++c)
    if (s.fit[c].name == "time_offset") return c;
  return s.fit.size() + k;
}

void broadcast_matrix(Eigen::MatrixXd& m) {
  std::vector<double> flat(m.data(), m.data() + m.size());
  flat.push_back(static_cast<double>(m.rows()));
  broadcast_from_rank0(flat);
  const auto rows = static_cast<Eigen::Index>(flat.back());
  flat.pop_back();
  const Eigen::Index cols = rows == 0 ? 0 : static_cast<Eigen::Index>(flat.size()) / rows;
  m = Eigen::Map<const Eigen::MatrixXd>(flat.data(), rows, cols);
}

// The simulated-parameter columns by central (or one-sided, at a bound)
// differences: 2 p runs over the task farm. Rank 0 fills `j`.
std::string difference_columns(const CalibrationStudy& s, const std::vector<double>& values,
                               const std::vector<double>& offsets, const Eigen::VectorXd& centre,
                               int progress_interval_s, Eigen::MatrixXd& j) {
  const std::vector<std::size_t> simulated = s.simulated();
  Eigen::VectorXd x(static_cast<Eigen::Index>(simulated.size())), lower(x.size()), upper(x.size()), typical(x.size());
  for (std::size_t c = 0; c < simulated.size(); ++c) {
    const FitParameter& f = s.fit[simulated[c]];
    const auto i = static_cast<Eigen::Index>(c);
    x[i] = values[simulated[c]];
    lower[i] = f.lower;
    upper[i] = f.upper;
    // finite_difference_steps takes h = cbrt(eps) max(|x|, typical); this
    // typical makes h = kJacobianRelativeStep max(|x|, 1 % of the range).
    typical[i] = kJacobianRelativeStep / std::cbrt(std::numeric_limits<double>::epsilon()) *
                 std::max(std::abs(x[i]), 1e-2 * (f.upper - f.lower));
  }
  const std::vector<DifferenceStep> steps = finite_difference_steps(x, lower, upper, typical);
  std::vector<int> tasks;  // 2 c: x + h e_c; 2 c + 1: x - h e_c (central only)
  for (std::size_t c = 0; c < steps.size(); ++c) {
    tasks.push_back(static_cast<int>(2 * c));
    if (steps[c].scheme == DifferenceScheme::central) tasks.push_back(static_cast<int>(2 * c + 1));
  }
  auto compute = [&](int task) {
    std::vector<double> v = values;
    const std::size_t c = static_cast<std::size_t>(task) / 2;
    v[simulated[c]] += (task % 2 == 0 ? 1.0 : -1.0) * steps[c].step;
    TaskResult result{task, 0, "", {}};
    for (std::size_t k = 0; k < s.datasets.size(); ++k) {
      const CalibrationCurve curve = simulate_calibration_curve(s, k, v);
      if (!curve.ok) return TaskResult{task, 1, curve.message, {}};
      const auto r = shifted_residuals(curve.t_s, curve.z_m, s.datasets[k].t, s.datasets[k].z, offsets[k]);
      result.values.insert(result.values.end(), r.begin(), r.end());
    }
    return result;
  };
  TaskFarmOptions farm;
  farm.label = "calibrate: Jacobian";
  farm.progress_interval_s = progress_interval_s;
  farm.stop = &InterruptGuard::flag();
  const std::vector<TaskResult> runs = run_task_farm(tasks, compute, {}, farm);
  if (world_rank() != 0) return "";
  if (runs.size() != tasks.size()) return "interrupted before the Jacobian was complete";
  std::vector<const TaskResult*> by_task(2 * steps.size(), nullptr);
  for (const TaskResult& r : runs) {
    if (r.status != 0) return "a Jacobian run failed (" + r.message + ")";
    by_task[static_cast<std::size_t>(r.index)] = &r;
  }
  for (std::size_t c = 0; c < steps.size(); ++c) {
    const bool central = steps[c].scheme == DifferenceScheme::central;
    const Eigen::Map<const Eigen::VectorXd> plus(by_task[2 * c]->values.data(), centre.size());
    const Eigen::VectorXd minus =
        central ? Eigen::Map<const Eigen::VectorXd>(by_task[2 * c + 1]->values.data(), centre.size()).eval() : centre;
    j.col(static_cast<Eigen::Index>(simulated[c])) = (plus - minus) / (central ? 2.0 * steps[c].step : steps[c].step);
  }
  return "";
}

// d r_i / d offset_k = -z'(t_i - offset_k) on curve k's rows: a central
// difference of the shifted curve over one output interval (no simulation).
void offset_columns(const CalibrationStudy& s, const std::vector<CalibrationCurve>& curves,
                    const std::vector<double>& offsets, Eigen::MatrixXd& j) {
  const std::vector<std::size_t> first = first_rows(s);
  for (std::size_t k = 0; k < s.datasets.size(); ++k) {
    const CalibrationDataset& d = s.datasets[k];
    const CalibrationCurve& curve = curves[k];
    const double h = 0.5 * (curve.t_s[1] - curve.t_s[0]);
    const auto plus = shifted_residuals(curve.t_s, curve.z_m, d.t, d.z, offsets[k] + h);
    const auto minus = shifted_residuals(curve.t_s, curve.z_m, d.t, d.z, offsets[k] - h);
    for (std::size_t i = 0; i < d.t.size(); ++i)
      j(static_cast<Eigen::Index>(first[k] + i), static_cast<Eigen::Index>(offset_column(s, k))) =
          (plus[i] - minus[i]) / (2.0 * h);
  }
}

}  // namespace

CalibrationJacobian calibration_jacobian(const CalibrationStudy& s, const std::vector<double>& values,
                                         const std::vector<double>& offsets, int progress_interval_s) {
  const std::size_t K = s.datasets.size();
  const std::size_t columns = s.fit.size() + (s.offset_fitted() ? 0 : K);
  const auto n = static_cast<Eigen::Index>(first_rows(s).back());
  CalibrationJacobian out;
  out.jacobian = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(columns));
  out.residuals.resize(n);
  std::vector<CalibrationCurve> curves;
  Eigen::Index row = 0;
  for (std::size_t k = 0; k < K; ++k) {
    curves.push_back(simulate_calibration_curve(s, k, values));
    if (!curves.back().ok) {
      out.message = "the run at the point itself failed (" + curves.back().message + ")";
      return out;
    }
    for (double r : shifted_residuals(curves[k].t_s, curves[k].z_m, s.datasets[k].t, s.datasets[k].z, offsets[k]))
      out.residuals[row++] = r;
  }
  out.message = difference_columns(s, values, offsets, out.residuals, progress_interval_s, out.jacobian);
  std::vector<double> failed{out.message.empty() ? 0.0 : 1.0};
  broadcast_from_rank0(failed);
  if (failed[0] != 0.0) {
    if (out.message.empty()) out.message = "a Jacobian run failed";
    return out;
  }
  broadcast_matrix(out.jacobian);
  offset_columns(s, curves, offsets, out.jacobian);
  out.ok = true;
  return out;
}

namespace {

// The iterations' coordinates: the simulated parameters (log10 where
// log-scale), then each curve's offset.
struct InternalLayout {
  std::vector<std::size_t> simulated;
  std::size_t curves = 0;
  Eigen::Index size() const { return static_cast<Eigen::Index>(simulated.size() + curves); }
};

struct FitPoint {
  std::vector<double> values, offsets;
};

FitPoint natural_point(const CalibrationStudy& s, const InternalLayout& layout, const Eigen::VectorXd& x) {
  FitPoint p;
  p.values.assign(s.fit.size(), 0.0);
  for (std::size_t c = 0; c < layout.simulated.size(); ++c)
    p.values[layout.simulated[c]] = fit_natural(s.fit[layout.simulated[c]], x[static_cast<Eigen::Index>(c)]);
  for (std::size_t k = 0; k < layout.curves; ++k)
    p.offsets.push_back(x[static_cast<Eigen::Index>(layout.simulated.size() + k)]);
  if (s.offset_fitted()) p.values[offset_column(s, 0)] = p.offsets[0];
  return p;
}

// One round of weighted least squares from x0 with fixed curve weights.
LevenbergMarquardtResult weighted_round(const CalibrationStudy& s, const InternalLayout& layout,
                                        const Eigen::VectorXd& x0, const std::vector<double>& weights,
                                        int max_iterations, int progress_interval_s,
                                        std::vector<CalibrationEvaluation>& history) {
  const std::vector<std::size_t> first = first_rows(s);
  Eigen::VectorXd lower(layout.size()), upper(layout.size());
  for (std::size_t c = 0; c < layout.simulated.size(); ++c) {
    const FitParameter& f = s.fit[layout.simulated[c]];
    lower[static_cast<Eigen::Index>(c)] = fit_internal(f, f.lower);
    upper[static_cast<Eigen::Index>(c)] = fit_internal(f, f.upper);
  }
  const bool fitted_offset = s.offset_fitted();
  for (std::size_t k = 0; k < layout.curves; ++k) {
    const auto i = static_cast<Eigen::Index>(layout.simulated.size() + k);
    lower[i] = fitted_offset ? s.fit[offset_column(s, 0)].lower : s.offset_min_s;
    upper[i] = fitted_offset ? s.fit[offset_column(s, 0)].upper : s.offset_max_s;
  }
  auto weigh = [&](Eigen::VectorXd& r) {
    for (std::size_t k = 0; k < layout.curves; ++k)
      r.segment(static_cast<Eigen::Index>(first[k]), static_cast<Eigen::Index>(first[k + 1] - first[k])) *= weights[k];
  };
  std::string failed_run;  // the first run that failed, named by its curve
  LeastSquaresResidualFunction residuals = [&](const Eigen::VectorXd& x) -> std::optional<Eigen::VectorXd> {
    const FitPoint p = natural_point(s, layout, x);
    CalibrationEvaluation e{p.values, p.offsets, 0, 0, 1};
    Eigen::VectorXd r(static_cast<Eigen::Index>(first.back()));
    for (std::size_t k = 0; k < layout.curves; ++k) {
      const CalibrationCurve curve = simulate_calibration_curve(s, k, p.values);
      if (!curve.ok) {
        if (failed_run.empty())
          failed_run = "curve " + std::to_string(k + 1) + " (" + s.datasets[k].path + " on " +
                       s.datasets[k].scenario_path + "): " + curve.message;
        history.push_back(e);
        return std::nullopt;
      }
      const auto rk = shifted_residuals(curve.t_s, curve.z_m, s.datasets[k].t, s.datasets[k].z, p.offsets[k]);
      r.segment(static_cast<Eigen::Index>(first[k]), static_cast<Eigen::Index>(rk.size())) =
          Eigen::Map<const Eigen::VectorXd>(rk.data(), static_cast<Eigen::Index>(rk.size()));
    }
    e.status = 0;
    e.rms_m = std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
    weigh(r);
    e.objective = 0.5 * r.squaredNorm();
    history.push_back(e);
    return r;
  };
  LeastSquaresJacobianFunction jacobian = [&](const Eigen::VectorXd& x, const Eigen::VectorXd&) -> std::optional<Eigen::MatrixXd> {
    const FitPoint p = natural_point(s, layout, x);
    CalibrationJacobian j = calibration_jacobian(s, p.values, p.offsets, progress_interval_s);
    if (!j.ok) return std::nullopt;
    Eigen::MatrixXd internal(j.jacobian.rows(), layout.size());
    for (std::size_t c = 0; c < layout.simulated.size(); ++c) {  // chain rule: d v / d log10 v = v ln 10
      const std::size_t column = layout.simulated[c];
      const double scale = s.fit[column].log_scale ? p.values[column] * kLn10 : 1.0;
      internal.col(static_cast<Eigen::Index>(c)) = j.jacobian.col(static_cast<Eigen::Index>(column)) * scale;
    }
    for (std::size_t k = 0; k < layout.curves; ++k)
      internal.col(static_cast<Eigen::Index>(layout.simulated.size() + k)) =
          j.jacobian.col(static_cast<Eigen::Index>(offset_column(s, k)));
    for (Eigen::Index c = 0; c < internal.cols(); ++c) {
      Eigen::VectorXd column = internal.col(c);
      weigh(column);
      internal.col(c) = column;
    }
    return internal;
  };
  LevenbergMarquardtSettings settings;
  settings.max_iterations = max_iterations;
  settings.step_tolerance = kStepTolerance;
  settings.gradient_tolerance = kGradientTolerance;
  settings.decrease_tolerance = kDecreaseTolerance;
  LevenbergMarquardtResult fit = levenberg_marquardt(residuals, jacobian, x0, lower, upper, settings);
  if (fit.stop == LeastSquaresStop::kEvaluationFailed && !failed_run.empty())
    fit.message += ": the run of " + failed_run;
  return fit;
}

// Each curve's RMS at a point (NaN where its run failed).
std::vector<double> curve_rms(const CalibrationStudy& s, const FitPoint& p) {
  std::vector<double> rms;
  for (std::size_t k = 0; k < s.datasets.size(); ++k) {
    const CalibrationCurve curve = simulate_calibration_curve(s, k, p.values);
    rms.push_back(curve.ok ? shifted_rms(curve.t_s, curve.z_m, s.datasets[k].t, s.datasets[k].z, p.offsets[k])
                           : std::nan(""));
  }
  return rms;
}

}  // namespace

LeastSquaresCalibration least_squares_calibration(const CalibrationStudy& s, const std::vector<double>& start,
                                                  int progress_interval_s) {
  InternalLayout layout{s.simulated(), s.datasets.size()};
  Eigen::VectorXd x(layout.size());
  for (std::size_t c = 0; c < layout.simulated.size(); ++c)
    x[static_cast<Eigen::Index>(c)] = fit_internal(s.fit[layout.simulated[c]], start[layout.simulated[c]]);
  for (std::size_t k = 0; k < layout.curves; ++k) {  // the offsets start at their profiled best
    const CalibrationCurve curve = simulate_calibration_curve(s, k, start);
    double offset = s.offset_fitted() ? start[offset_column(s, 0)] : s.offset_initial_s;
    if (curve.ok && !s.offset_fitted())
      offset = best_offset(curve.t_s, curve.z_m, s.datasets[k].t, s.datasets[k].z, s.offset_min_s, s.offset_max_s);
    x[static_cast<Eigen::Index>(layout.simulated.size() + k)] = offset;
  }
  const int max_iterations = s.max_iterations > 0 ? s.max_iterations : 10 + 5 * static_cast<int>(s.fit.size());
  LeastSquaresCalibration out;
  std::vector<double> weights(layout.curves, 1.0);
  LevenbergMarquardtResult lm;
  for (int round = 0; round < (layout.curves == 1 ? 1 : kMaxWeightRounds); ++round) {
    lm = weighted_round(s, layout, x, weights, max_iterations, progress_interval_s, out.history);
    out.iterations += lm.iterations;
    x = lm.x;
    if (layout.curves == 1 || !lm.converged) break;
    const std::vector<double> rms = curve_rms(s, natural_point(s, layout, x));
    bool settled = true;
    for (std::size_t k = 0; k < layout.curves; ++k) {
      const double w = rms[k] > 0 ? 1.0 / rms[k] : 1.0;
      settled = settled && std::abs(w - weights[k]) <= kWeightTolerance * w;
      weights[k] = w;
    }
    if (settled) break;
    if (round + 1 == kMaxWeightRounds) {
      lm.converged = false;
      lm.message = "the curves' weights did not settle in " + std::to_string(kMaxWeightRounds) + " rounds";
    }
  }
  const FitPoint best = natural_point(s, layout, x);
  out.values = best.values;
  out.offsets = best.offsets;
  out.stop = lm.stop;
  out.converged = lm.converged;
  out.message = lm.message;
  return out;
}

IntegrationShift integration_shift(const CalibrationStudy& s, const std::vector<double>& values,
                                   const std::vector<double>& offsets, const std::vector<double>& weights,
                                   const Eigen::MatrixXd& weighted_jacobian, const Eigen::VectorXd& standard_error) {
  const CalibrationStudy reference = s.with_integrator(s.integration_check.reference);
  const std::vector<std::size_t> first = first_rows(s);
  Eigen::VectorXd difference(static_cast<Eigen::Index>(first.back()));
  IntegrationShift out;
  for (std::size_t k = 0; k < s.datasets.size(); ++k) {
    const CalibrationCurve fast = simulate_calibration_curve(s, k, values);
    const CalibrationCurve exact = simulate_calibration_curve(reference, k, values);
    if (!fast.ok || !exact.ok) {
      out.message = "a run of the integration check failed (" + (fast.ok ? exact.message : fast.message) + ")";
      return out;
    }
    const CalibrationDataset& d = s.datasets[k];
    const auto r_fast = shifted_residuals(fast.t_s, fast.z_m, d.t, d.z, offsets[k]);
    const auto r_exact = shifted_residuals(exact.t_s, exact.z_m, d.t, d.z, offsets[k]);
    for (std::size_t i = 0; i < d.t.size(); ++i)
      difference[static_cast<Eigen::Index>(first[k] + i)] = weights[k] * (r_exact[i] - r_fast[i]);
  }
  // The reference's optimum lies one Gauss-Newton step away: J d = -difference.
  const Eigen::VectorXd step = weighted_jacobian.colPivHouseholderQr().solve(-difference);
  for (std::size_t c = 0; c < s.fit.size(); ++c) {
    const auto i = static_cast<Eigen::Index>(c);
    out.step.push_back(step[i]);
    out.shift_se.push_back(step[i] / standard_error[i]);
    if (std::isfinite(out.shift_se.back()))
      out.largest_se = std::max(out.largest_se, std::abs(out.shift_se.back()));
    else
      out.largest_se = std::numeric_limits<double>::infinity();
  }
  out.ok = true;
  return out;
}

}  // namespace rover::study
