// Profile-likelihood intervals of a calibration fit (calibration_checked_fit.hpp).
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
#include "study/studies/stoppable_optimization.hpp"
#include "study/studies/report_number.hpp"

#include <functional>

#include <nlopt.hpp>

namespace rover::study {

namespace {

// The fitted parameters other than `fixed` re-optimised with BOBYQA (at most
// max_evaluations simulations) from `values`, the offsets profiled.
void reoptimise_others(const CalibrationStudy& s, std::size_t fixed, std::vector<double>& values) {
  const std::size_t p = s.fit.size();
  std::vector<std::size_t> free;
  for (std::size_t k = 0; k < p; ++k)
    if (k != fixed) free.push_back(k);
  if (!free.empty()) {
    std::vector<double> x, lower, upper;
    for (std::size_t k : free) {
      x.push_back(fit_internal(s.fit[k], values[k]));
      lower.push_back(fit_internal(s.fit[k], s.fit[k].lower));
      upper.push_back(fit_internal(s.fit[k], s.fit[k].upper));
    }
    std::function<double(const std::vector<double>&)> objective = [&](const std::vector<double>& xi) {
      std::vector<double> v = values;
      for (std::size_t k = 0; k < free.size(); ++k) v[free[k]] = fit_natural(s.fit[free[k]], xi[k]);
      return fit_objective(s, v).objective;
    };
    nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(free.size()));
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
    opt.set_maxeval(s.max_evaluations);
    opt.set_xtol_rel(s.xtol_rel);
    double minimum = 0;
    try {  // a signal ends the search at once, and this grid point is not done (WorkStopped)
      optimize_stoppably(opt, x, minimum, objective);
    } catch (const nlopt::roundoff_limited&) {
    }
    for (std::size_t k = 0; k < free.size(); ++k) values[free[k]] = fit_natural(s.fit[free[k]], x[k]);
  }
}

// Rank 0: each parameter's profile from the grid runs (task i G + g: grid
// point g of parameter i).
std::vector<ParameterProfile> assemble_profiles(const CalibrationStudy& s, const std::vector<std::size_t>& profiled,
                                                const std::vector<TaskResult>& runs, std::size_t G,
                                                const std::function<double(std::size_t, std::size_t)>& grid_value) {
  std::vector<ParameterProfile> profiles;
  for (std::size_t i = 0; i < profiled.size(); ++i) {
    ParameterProfile prof;
    prof.name = s.fit[profiled[i]].name;
    for (const TaskResult& r : runs)
      if (static_cast<std::size_t>(r.index) / G == i && r.status == 0) {
        prof.values.push_back(grid_value(i, static_cast<std::size_t>(r.index) % G));
        prof.weighted_rss.push_back(r.values.at(0));
      }
    prof.complete = prof.values.size() >= 3;
    if (prof.complete) prof.interval = profile_likelihood_interval(prof.values, prof.weighted_rss, 1.0, 0.95);
    profiles.push_back(std::move(prof));
  }
  return profiles;
}

}  // namespace

std::vector<ParameterProfile> profile_parameters(const CalibrationStudy& s, const GaussNewtonResult& gn,
                                                 std::vector<double> best, const StudyRunOptions& control) {
  const std::size_t p = s.fit.size(), K = s.datasets.size();
  const std::size_t G = static_cast<std::size_t>(s.profile_points);
  // Rank 0 lays out the grids and the noise sds; every rank gets them.
  std::vector<double> layout;  // best (p + K), noise sd (K), then per parameter G values
  std::vector<std::size_t> profiled;
  for (std::size_t j = 0; j < p; ++j)
    if (s.fit[j].name != "time_offset") profiled.push_back(j);
  if (world_rank() == 0) {
    layout = best;
    for (std::size_t k = 0; k < K; ++k) layout.push_back(gn.ok ? gn.noise_sd[k] : 0.0);
    for (std::size_t j : profiled) {
      const FitParameter& f = s.fit[j];
      const double se = gn.ok ? gn.uncertainty.standard_error[static_cast<Eigen::Index>(j)] : NAN;
      double lo = f.lower, hi = f.upper;
      if (std::isfinite(se) && se > 0) {
        lo = std::max(f.lower, best[j] - 4.0 * se);
        hi = std::min(f.upper, best[j] + 4.0 * se);
      }
      for (std::size_t g = 0; g < G; ++g) {
        const double u = static_cast<double>(g) / static_cast<double>(G - 1);
        layout.push_back(f.log_scale && !(std::isfinite(se) && se > 0)
                             ? std::exp(std::log(lo) + u * (std::log(hi) - std::log(lo)))
                             : lo + u * (hi - lo));
      }
    }
  }
  broadcast_from_rank0(layout);
  best.assign(layout.begin(), layout.begin() + static_cast<std::ptrdiff_t>(p + K));
  const std::vector<double> noise_sd(layout.begin() + static_cast<std::ptrdiff_t>(p + K),
                                     layout.begin() + static_cast<std::ptrdiff_t>(p + 2 * K));
  auto grid_value = [&](std::size_t i, std::size_t g) { return layout[p + 2 * K + i * G + g]; };
  if (std::any_of(noise_sd.begin(), noise_sd.end(), [](double v) { return !(v > 0); })) return {};

  auto compute = [&](int task) {
    const std::size_t i = static_cast<std::size_t>(task) / G, g = static_cast<std::size_t>(task) % G;
    const std::size_t fixed = profiled[i];
    std::vector<double> values(best.begin(), best.begin() + static_cast<std::ptrdiff_t>(p));
    values[fixed] = grid_value(i, g);
    reoptimise_others(s, fixed, values);
    const CalibrationResiduals r = calibration_residuals(s, values);
    if (!r.ok) return TaskResult{task, 1, r.message, {}};
    double weighted = 0;
    for (std::size_t k = 0; k < K; ++k)
      for (double v : r.residuals[k]) weighted += v * v / (noise_sd[k] * noise_sd[k]);
    return TaskResult{task, 0, "", {weighted}};
  };
  std::vector<int> tasks(profiled.size() * G);
  for (std::size_t t = 0; t < tasks.size(); ++t) tasks[t] = static_cast<int>(t);
  TaskFarmOptions farm;
  farm.label = "calibrate: profiles";
  farm.progress_interval_s = control.progress_interval_s;
  farm.stop = &InterruptGuard::flag();
  const std::vector<TaskResult> runs = run_task_farm(tasks, compute, {}, farm);
  if (world_rank() != 0) return {};
  return assemble_profiles(s, profiled, runs, G, grid_value);
}

}  // namespace rover::study
