// The first search of a calibration fit by an NLopt algorithm, and the
// history of every evaluation of a fit (calibration_checked_fit.hpp).
#include "study/studies/calibration_checked_fit.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "study/estimators/work_stopped.hpp"
#include "study/runtime/rank0_broadcast.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/runtime/task_farm.hpp"
#include "study/studies/report_number.hpp"
#include "study/studies/stoppable_optimization.hpp"

#include <functional>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_real_distribution.hpp>
#include <nlopt.hpp>

namespace rover::study {

FitObjective fit_objective(const CalibrationStudy& s, const std::vector<double>& values) {
  const CalibrationResiduals r = calibration_residuals(s, values);
  FitObjective e;
  e.offsets.assign(s.datasets.size(), 0.0);
  if (!r.ok) {
    e.status = 1;
    e.rms = 1.0;  // a failed run is a very bad fit, not the end of the calibration
    e.objective = s.datasets.size() == 1 ? e.rms : 1e3;
    return e;
  }
  e.offsets = r.offsets;
  double rss = 0.0, log_sum = 0.0;
  std::size_t n = 0;
  for (const auto& residuals : r.residuals) {
    double rss_k = 0.0;
    for (double v : residuals) rss_k += v * v;
    rss += rss_k;
    n += residuals.size();
    log_sum += 0.5 * static_cast<double>(residuals.size()) *
               std::log(std::max(rss_k / static_cast<double>(residuals.size()), 1e-300));
  }
  e.rms = std::sqrt(rss / static_cast<double>(n));
  e.objective = s.datasets.size() == 1 ? e.rms : log_sum / static_cast<double>(n);
  return e;
}

// The first search of an NLopt algorithm: one task per start (fanned out and
// checkpointed); returns the best point (values, then offsets) on rank 0.
namespace {

// Appends every evaluation of every start to the history; returns the best
// successful point (values, then offsets) on rank 0.
std::vector<double> best_of_starts(const CalibrationStudy& s, const std::vector<TaskResult>& results,
                                   FitHistory& history) {
  const HistoryLayout row(s);
  std::size_t best_row = 0;
  double best_objective = std::numeric_limits<double>::infinity();
  for (const TaskResult& r : results) {
    history.messages.push_back("start " + std::to_string(r.index) + ": " + s.algorithm + " " + r.message);
    for (std::size_t k = 0; k + row.width() <= r.values.size(); k += row.width()) {
      const std::size_t e = history.rows.size() / row.width();
      history.rows.insert(history.rows.end(), r.values.begin() + static_cast<std::ptrdiff_t>(k),
                          r.values.begin() + static_cast<std::ptrdiff_t>(k + row.width()));
      history.start.push_back(r.index);
      if (r.values[k + row.status()] == 0 && r.values[k + row.objective()] < best_objective) {
        best_objective = r.values[k + row.objective()];
        best_row = e;
      }
    }
  }
  if (world_rank() == 0 && !std::isfinite(best_objective)) throw std::runtime_error("calibrate: no evaluation succeeded");
  std::vector<double> best;  // values, then offsets
  if (world_rank() == 0)
    best.assign(history.rows.begin() + static_cast<std::ptrdiff_t>(best_row * row.width()),
                history.rows.begin() + static_cast<std::ptrdiff_t>(best_row * row.width() + row.rms()));
  return best;
}

}  // namespace

std::vector<double> nlopt_search(const CalibrationStudy& s, const StudyRunOptions& control, const std::string& out,
                                 FitHistory& fit_history) {
  const std::size_t p = s.fit.size();

  // One task = one local (or global) NLopt search from its own start point;
  // its values are the history of every evaluation, row by row.
  auto compute = [&](int start) {
    std::vector<double> x(p), lower(p), upper(p);
    boost::random::mt19937_64 engine(s.seed * 1000003ull + static_cast<std::uint64_t>(start));
    for (std::size_t k = 0; k < p; ++k) {
      const FitParameter& f = s.fit[k];
      lower[k] = fit_internal(f, f.lower);
      upper[k] = fit_internal(f, f.upper);
      x[k] = start == 0 ? fit_internal(f, f.initial)
                        : boost::random::uniform_real_distribution<double>(lower[k], upper[k])(engine);
    }
    std::vector<double> history;
    std::function<double(const std::vector<double>&)> objective = [&](const std::vector<double>& xi) {
      std::vector<double> values(p);
      for (std::size_t k = 0; k < p; ++k) values[k] = fit_natural(s.fit[k], xi[k]);
      const FitObjective e = fit_objective(s, values);
      history.insert(history.end(), values.begin(), values.end());
      history.insert(history.end(), e.offsets.begin(), e.offsets.end());
      history.push_back(e.rms);
      history.push_back(e.objective);
      history.push_back(e.status);
      return e.objective;
    };
    nlopt::opt opt(s.algorithm.c_str(), static_cast<unsigned>(p));
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
    opt.set_maxeval(s.max_evaluations);
    opt.set_xtol_rel(s.xtol_rel);
    if (s.algorithm.find("MLSL") != std::string::npos || s.algorithm.find("AUGLAG") != std::string::npos) {
      nlopt::opt local(nlopt::LN_BOBYQA, static_cast<unsigned>(p));
      local.set_xtol_rel(s.xtol_rel);
      opt.set_local_optimizer(local);
    }
    nlopt::srand(s.seed + static_cast<unsigned long>(start));
    double best = 0.0;
    TaskResult result{start, 0, "", {}};
    try {  // a signal ends the search at once, and this start is not done (WorkStopped)
      const nlopt::result code = optimize_stoppably(opt, x, best, objective);
      result.message = nlopt_result_to_string(static_cast<nlopt_result>(code));
    } catch (const nlopt::roundoff_limited&) {
      result.message = "ROUNDOFF_LIMITED";
    } catch (const WorkStopped&) {
      throw;
    } catch (const std::exception& e) {
      if (history.empty()) throw;
      result.message = std::string("FAILURE: ") + e.what();
    }
    result.values = std::move(history);
    return result;
  };
  StudyRunOptions options{.results_path = out, .fingerprint = s.fingerprint, .resume = control.resume,
                          .label = "calibrate", .progress_interval_s = control.progress_interval_s,
                          .resume_command = control.resume_command, .checkpoint = control.checkpoint};
  const std::vector<TaskResult> results = run_study_tasks(s.starts, compute, options);

  return best_of_starts(s, results, fit_history);
}

// Appends the least-squares evaluations to the history (start index -1).
void append_history(const LeastSquaresCalibration& fit, FitHistory& history) {
  for (const CalibrationEvaluation& e : fit.history) {
    history.rows.insert(history.rows.end(), e.values.begin(), e.values.end());
    history.rows.insert(history.rows.end(), e.offsets.begin(), e.offsets.end());
    history.rows.insert(history.rows.end(), {e.rms_m, e.objective, static_cast<double>(e.status)});
    history.start.push_back(-1);
  }
  history.messages.push_back("least squares: " + fit.message);
}

}  // namespace rover::study
