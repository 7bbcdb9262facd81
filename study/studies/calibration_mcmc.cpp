// See calibration_mcmc.hpp.
#include "study/studies/calibration_mcmc.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <numbers>

#include <boost/histogram.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>

#include "io/checkpoint.hpp"
#include "io/hdf5_file.hpp"
#include "io/plot.hpp"
#include "study/runtime/calibration_mpi.hpp"
#include "study/estimators/ensemble_sampler.hpp"
#include "study/estimators/mcmc_diagnostics.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::study {
namespace {

constexpr double kNegativeInfinity = -std::numeric_limits<double>::infinity();

// Sample quantile with linear interpolation between order statistics
// (Hyndman & Fan 1996, type 7) of an unsorted copy.
double quantile_of(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const double h = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

std::string format_number(double v, int digits = 4) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
  return buffer;
}

std::string format_duration(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  return s >= 60 ? std::to_string(s / 60) + "m" + std::to_string(s % 60) + "s" : std::to_string(s) + "s";
}


// A sampled parameter as the corner plot shows it: its name and unit
// (study/studies/calibration.hpp), the noise sd in mm rather than metres.
struct CornerParameter {
  std::string label{};  // axis label, with unit
  double scale = 1.0;   // shown value = scale * sampled value
};
CornerParameter corner_parameter(const std::string& name) {
  if (name == "c_q") return {"c_q [N m s/rad]"};
  if (name == "f") return {"f [1/rad]"};
  if (name == "time_offset") return {"time_offset [s]"};
  if (name.starts_with("noise_sd")) return {name + " [mm]", 1e3};
  return {name};  // M0_scale, a factor
}

// The corner plot (Foreman-Mackey 2016) of the samples after `discard`
// burn-in steps, p x p panels for p parameters (samples[k]: steps x walkers):
// on the diagonal the marginal histogram of parameter k over all kept samples
// (square-root choice of the bin count, 5 to 40 bins) with the posterior
// mean (solid line) and 95 % interval (dashed), also in the panel's title;
// below it the scatter of parameter (column) against parameter (row) over at
// most 2000 samples spread evenly over the kept steps and walkers; blank
// above. The panels of a column share the x range of its histogram, those of
// a row the range of its parameter, so one parameter's axes line up.
io::PanelGrid corner_plot(const std::string& title, const std::vector<CornerParameter>& parameters,
                          const std::vector<Eigen::MatrixXd>& samples, long discard, const std::vector<double>& mean,
                          const std::vector<double>& q025, const std::vector<double>& q975) {
  constexpr long kMaxScatterPoints = 2000;
  constexpr int kMaxTicks = 5;
  const int p = static_cast<int>(parameters.size());
  const long steps = samples.front().rows(), walkers = samples.front().cols(), kept = steps - discard;
  std::vector<io::AxisRange> range(static_cast<std::size_t>(p));  // the histogram's edges, shown units
  io::PanelGrid grid{.title = title, .rows = p, .cols = p};
  grid.panels.resize(static_cast<std::size_t>(p * p));
  grid.width_px = grid.height_px = std::clamp(350 * p, 700, 3500);
  for (int k = 0; k < p; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double scale = parameters[i].scale;
    const Eigen::MatrixXd tail = scale * samples[i].bottomRows(kept);
    double lo = tail.minCoeff(), hi = tail.maxCoeff();
    if (!(hi > lo)) {  // one value (a stuck chain): a bin around it
      const double half = std::max(1e-12, 1e-3 * std::abs(lo));
      lo -= half;
      hi += half;
    }
    range[i] = {lo, hi};
    const int bins = std::clamp(static_cast<int>(std::lround(std::sqrt(static_cast<double>(tail.size())))), 5, 40);
    // The top edge nudged up so that the largest sample falls in the last bin, not the overflow.
    auto histogram = boost::histogram::make_histogram(
        boost::histogram::axis::regular<double>(static_cast<unsigned>(bins), lo, std::nextafter(hi, hi + 1.0)));
    for (Eigen::Index j = 0; j < tail.size(); ++j) histogram(tail.data()[j]);

    io::Band filled{.color = "#4060a0", .opacity = 0.3};
    io::Series outline{.color = "#4060a0", .line_width = 1.2};
    double highest = 0.0;
    for (int b = 0; b < bins; ++b) {
      const auto bin = histogram.axis().bin(b);
      const double count = histogram.at(b);
      highest = std::max(highest, count);
      for (const double edge : {bin.lower(), bin.upper()}) {
        filled.x.push_back(edge);
        filled.lower.push_back(0.0);
        filled.upper.push_back(count);
        outline.x.push_back(edge);
        outline.y.push_back(count);
      }
    }
    const double top = 1.1 * std::max(highest, 1.0);
    const double m = scale * mean[i], lower = scale * q025[i], upper = scale * q975[i];
    const double gap = std::numeric_limits<double>::quiet_NaN();
    io::LinePlot diagonal{.title = "mean " + format_number(m) + ", 95 % [" + format_number(lower) + ", " +
                                   format_number(upper) + "]",
                          .x_label = parameters[i].label,
                          .y_label = "samples per bin",
                          .x_range = range[i],
                          .y_range = io::AxisRange{0.0, top},
                          .max_ticks = kMaxTicks};
    diagonal.bands.push_back(std::move(filled));
    diagonal.series.push_back(std::move(outline));
    diagonal.series.push_back({.x = {m, m}, .y = {0.0, top}, .color = "dark-red"});
    diagonal.series.push_back({.x = {lower, lower, gap, upper, upper},
                               .y = {0.0, top, gap, 0.0, top},
                               .style = io::SeriesStyle::dashed,
                               .color = "dark-red"});
    grid.panels[i * static_cast<std::size_t>(p) + i] = std::move(diagonal);
  }
  // The scatter samples: evenly spread over the kept (step, walker) pairs, step-major.
  const long total = kept * walkers, shown = std::min(total, kMaxScatterPoints);
  std::vector<std::vector<double>> thinned(static_cast<std::size_t>(p));
  for (long j = 0; j < shown; ++j) {
    const long flat = j * total / shown, step = discard + flat / walkers, walker = flat % walkers;
    for (std::size_t k = 0; k < thinned.size(); ++k)
      thinned[k].push_back(parameters[k].scale * samples[k](step, walker));
  }
  for (std::size_t row = 1; row < thinned.size(); ++row)
    for (std::size_t column = 0; column < row; ++column) {
      io::LinePlot scatter{.x_label = parameters[column].label,
                           .y_label = parameters[row].label,
                           .x_range = range[column],
                           .y_range = range[row],
                           .max_ticks = kMaxTicks};
      scatter.series.push_back(
          {.x = thinned[column], .y = thinned[row], .style = io::SeriesStyle::points, .color = "#a0204080"});
      grid.panels[row * static_cast<std::size_t>(p) + column] = std::move(scatter);
    }
  return grid;
}

// Ensemble state <-> checkpoint record (positions row-major, log densities, accepted moves).
io::TaskRecord state_record(const EnsembleState& state, long accepted_in_step) {
  io::TaskRecord r;
  r.index = static_cast<int>(state.step);
  r.values.assign(state.positions.data(), state.positions.data() + state.positions.size());
  r.values.insert(r.values.end(), state.log_density.begin(), state.log_density.end());
  r.values.push_back(static_cast<double>(accepted_in_step));
  return r;
}
EnsembleState state_from_values(const std::vector<double>& v, long step, int walkers, int p) {
  EnsembleState state;
  state.step = step;
  state.positions.resize(walkers, p);
  std::copy(v.begin(), v.begin() + walkers * p, state.positions.data());
  state.log_density.resize(walkers);
  for (int k = 0; k < walkers; ++k) state.log_density[k] = v[static_cast<std::size_t>(walkers * p + k)];
  return state;
}

// The chain's convergence target is checked every this many steps.
constexpr long kMcmcCheckInterval = 50;

// Records 1 .. steps as per-parameter steps x walkers matrices, the log
// posterior and the accepted moves.
struct ChainSamples {
  std::vector<Eigen::MatrixXd> samples;
  Eigen::MatrixXd log_posterior;
  long accepted_moves = 0;
};
ChainSamples chain_samples(const std::vector<io::TaskRecord>& records, long steps, int walkers, int p) {
  ChainSamples c{std::vector<Eigen::MatrixXd>(static_cast<std::size_t>(p), Eigen::MatrixXd(steps, walkers)),
                 Eigen::MatrixXd(steps, walkers), 0};
  for (long st = 1; st <= steps; ++st) {
    const std::vector<double>& v = records[static_cast<std::size_t>(st)].values;
    for (int w = 0; w < walkers; ++w) {
      for (int k = 0; k < p; ++k) c.samples[static_cast<std::size_t>(k)](st - 1, w) = v[static_cast<std::size_t>(w * p + k)];
      c.log_posterior(st - 1, w) = v[static_cast<std::size_t>(walkers * p + w)];
    }
    c.accepted_moves += std::lround(v.back());
  }
  return c;
}

// Whether the chain so far meets the study's target, and a line saying how far it is.
bool target_met(const ChainDiagnostics& d, const McmcSettings& m, std::string* progress) {
  const double ess = d.effective_sample_size.size() ? d.effective_sample_size.minCoeff() : 0.0;
  const double rhat = d.nested_rhat.size() ? d.nested_rhat.maxCoeff() : INFINITY;
  *progress = "smallest effective sample size " + format_number(ess, 3) + " (target " + format_number(m.target_ess, 3) +
              "), largest nested R-hat " + format_number(rhat, 4) + " (target < " + format_number(m.max_rhat, 4) + ")";
  return ess >= m.target_ess && rhat < m.max_rhat;
}

}  // namespace

double gaussian_log_likelihood(const std::vector<double>& residuals, double noise_sd) {
  double rss = 0.0;
  for (double r : residuals) rss += r * r;
  const double n = static_cast<double>(residuals.size());
  return -0.5 * n * std::log(2.0 * std::numbers::pi * noise_sd * noise_sd) - rss / (2.0 * noise_sd * noise_sd);
}

double calibration_log_density(const std::vector<Distribution>& priors, const Distribution& noise_prior,
                               std::optional<double> known_noise_sd, std::size_t curves,
                               const Eigen::VectorXd& theta, const ResidualFunction& residuals) {
  const std::size_t p = priors.size();
  double log_density = 0.0;
  std::vector<double> parameters(p);
  for (std::size_t k = 0; k < p; ++k) {
    parameters[k] = theta[static_cast<Eigen::Index>(k)];
    log_density += priors[k].log_pdf(parameters[k]);
  }
  std::vector<double> sd(curves, known_noise_sd.value_or(0.0));
  for (std::size_t k = 0; k < curves && !known_noise_sd; ++k) {
    sd[k] = theta[static_cast<Eigen::Index>(p + k)];
    log_density += noise_prior.log_pdf(sd[k]);
  }
  if (!(log_density > kNegativeInfinity) || !std::all_of(sd.begin(), sd.end(), [](double v) { return v > 0; }))
    return kNegativeInfinity;
  const std::optional<std::vector<std::vector<double>>> r = residuals(parameters);
  if (!r) return kNegativeInfinity;
  if (r->size() != curves) throw std::invalid_argument("calibration_log_density: residuals of a wrong number of curves");
  for (std::size_t k = 0; k < curves; ++k) log_density += gaussian_log_likelihood((*r)[k], sd[k]);
  return log_density;
}

CalibrationOutcome run_calibration_mcmc(const CalibrationStudy& s, const StudyRunControl& control,
                                        const McmcStart& start) {
  const InterruptGuard guard;
  const std::string out = results_path(s.common, control.results_path);
  const McmcSettings& m = s.mcmc;
  const int p_fit = static_cast<int>(s.fit.size());
  const std::size_t curves = s.datasets.size();
  const int p = p_fit + (m.sample_noise ? static_cast<int>(curves) : 0);
  const int walkers = m.walkers;
  const bool root = world_rank() == 0;
  std::vector<std::string> names;
  std::vector<Distribution> priors;
  for (const auto& f : s.fit) {
    names.push_back(f.name);
    priors.push_back(f.prior);
  }
  for (std::size_t k = 0; k < curves && m.sample_noise; ++k)
    names.push_back(curves == 1 ? "noise_sd" : "noise_sd[" + std::to_string(k) + "]");
  const std::optional<double> known_sd =
      m.sample_noise ? std::nullopt : std::optional<double>(m.known_noise_sd_m);

  // One half-ensemble's proposals: one task farm over all ranks, the log
  // densities broadcast from rank 0 so every rank holds the same state.
  const BatchLogDensity batch = [&](const DesignMatrix& points) {
    auto compute = [&](int i) {
      const Eigen::VectorXd theta = points.row(i).transpose();
      const double lp = calibration_log_density(
          priors, m.noise_prior, known_sd, curves, theta, [&](const std::vector<double>& values) {
            CalibrationResiduals fit = calibration_residuals(s, values);
            return fit.ok ? std::optional<std::vector<std::vector<double>>>(std::move(fit.residuals)) : std::nullopt;
          });
      return TaskResult{i, 0, "", {lp}};
    };
    std::vector<int> tasks(static_cast<std::size_t>(points.rows()));
    for (std::size_t i = 0; i < tasks.size(); ++i) tasks[i] = static_cast<int>(i);
    TaskFarmOptions farm;
    farm.progress = nullptr;
    const std::vector<TaskResult> results = run_task_farm(tasks, compute, {}, farm);
    std::vector<double> values(tasks.size(), kNegativeInfinity);
    for (const TaskResult& r : results)
      if (r.status == 0 && !r.values.empty()) values[static_cast<std::size_t>(r.index)] = r.values[0];
    broadcast_from_rank0(values);
    Eigen::VectorXd lp(points.rows());
    for (Eigen::Index i = 0; i < lp.size(); ++i) {
      const double v = values[static_cast<std::size_t>(i)];
      lp[i] = std::isnan(v) ? kNegativeInfinity : v;
    }
    return lp;
  };

  // The checkpoint (rank 0): record k = the state after step k (0 = initial).
  io::CheckpointPolicy policy = control.checkpoint;
  policy.every_records = 1;
  std::optional<io::ResultCheckpoint> checkpoint;
  std::vector<io::TaskRecord> records;
  if (root) {
    checkpoint.emplace(out, s.fingerprint, policy);
    if (control.resume) records = checkpoint->load();
    // Keep the contiguous prefix 0 .. k.
    std::size_t contiguous = 0;
    while (contiguous < records.size() && records[contiguous].index == static_cast<int>(contiguous)) ++contiguous;
    records.resize(contiguous);
  }
  std::vector<double> resume_state;
  if (root && !records.empty()) {
    resume_state = records.back().values;
    resume_state.push_back(static_cast<double>(records.back().index));
  }
  broadcast_from_rank0(resume_state);

  EnsembleState state;
  if (!resume_state.empty()) {
    state = state_from_values(resume_state, std::lround(resume_state.back()), walkers, p);
    if (root)
      std::cerr << "calibrate: resuming the ensemble after step " << state.step << " from "
                << checkpoint->path() << "\n";
  } else {
    // Walkers start in a small ball around the initial values (2 % of the
    // prior's width or 10 % of its sd); the noise sd around the RMS there.
    std::vector<double> start_values = start.values;
    if (start_values.empty())
      for (const auto& f : s.fit) start_values.push_back(f.initial);
    std::vector<double> start_sd(curves, known_sd.value_or(1e-3));
    if (m.sample_noise) {
      const CalibrationResiduals fit = calibration_residuals(s, start_values);
      for (std::size_t c = 0; c < curves && fit.ok; ++c) {
        double ss = 0;
        for (double r : fit.residuals[c]) ss += r * r;
        start_sd[c] = std::sqrt(std::max(1e-30, ss / static_cast<double>(fit.residuals[c].size())));
      }
    }
    boost::random::mt19937_64 engine(m.seed);
    boost::random::normal_distribution<double> gauss;
    DesignMatrix positions(walkers, p);
    for (int w = 0; w < walkers; ++w) {
      for (int k = 0; k < p; ++k) {
        const bool noise = k >= p_fit;
        const Distribution& prior = noise ? m.noise_prior : priors[static_cast<std::size_t>(k)];
        const double centre = noise ? start_sd[static_cast<std::size_t>(k - p_fit)] : start_values[static_cast<std::size_t>(k)];
        const double lo = prior.support_lower(), hi = prior.support_upper();
        const double fit_se = !noise && !start.standard_error.empty() ? start.standard_error[static_cast<std::size_t>(k)] : 0.0;
        const double spread = noise ? 0.1 * centre
                              : std::isfinite(fit_se) && fit_se > 0 ? 0.1 * fit_se
                              : std::isfinite(hi - lo) ? 0.02 * (hi - lo) : 0.1 * prior.sd();
        double v = centre + spread * gauss(engine);
        for (int tries = 0; tries < 100 && !(v > lo && v < hi); ++tries) v = centre + spread * gauss(engine);
        if (!(v > lo && v < hi)) v = centre;
        positions(w, k) = v;
      }
    }
    state = initial_ensemble_state(positions, batch);
    if (root) checkpoint->add(state_record(state, 0));
  }

  // Sampling, one checkpointed step at a time, with progress and time left.
  const EnsembleOptions options{.walkers = walkers, .stretch_scale = 2.0, .seed = m.seed};
  const auto started = std::chrono::steady_clock::now();
  auto last_report = started;
  const long first_step = state.step;
  std::vector<bool> accepted;
  bool interrupted = false;
  std::vector<io::TaskRecord> chain_records = records;  // rank 0: the chain so far, in memory
  if (root && chain_records.empty()) chain_records = checkpoint->load();
  bool mixed = false;
  std::string progress;
  while (state.step < m.steps) {
    state = ensemble_step(state, batch, options, &accepted);
    if (root) {
      chain_records.push_back(state_record(state, std::count(accepted.begin(), accepted.end(), true)));
      checkpoint->add(chain_records.back());
      if (m.target_ess > 0 && state.step >= m.discard + kMcmcCheckInterval && state.step % kMcmcCheckInterval == 0) {
        const ChainSamples chain = chain_samples(chain_records, state.step, walkers, p);
        mixed = target_met(diagnose_chain(chain.samples, chain.accepted_moves, static_cast<int>(m.discard)), m,
                           &progress);
        std::cerr << "calibrate: step " << state.step << ": " << progress << "\n";
      }
      const auto now = std::chrono::steady_clock::now();
      if (control.progress_interval_s > 0 &&
          std::chrono::duration<double>(now - last_report).count() >= control.progress_interval_s) {
        last_report = now;
        const double elapsed = std::chrono::duration<double>(now - started).count();
        const double per_step = elapsed / static_cast<double>(state.step - first_step);
        std::cerr << "calibrate: step " << state.step << " (at most " << m.steps << "), "
                  << format_number(per_step, 3) << " s/step, time left "
                  << format_duration(per_step * static_cast<double>(m.steps - state.step)) << " at most\n";
      }
    }
    std::vector<double> stop{root && InterruptGuard::flag().load() ? 1.0 : 0.0, mixed ? 1.0 : 0.0};
    broadcast_from_rank0(stop);
    if (stop[0] != 0.0 && state.step < m.steps) {
      interrupted = true;
      break;
    }
    if (stop[1] != 0.0) break;  // the target is met
  }
  if (root) checkpoint->save();
  if (interrupted) {
    if (!root) return {out, true, ""};
    throw StudyInterrupted("calibrate: interrupted after step " + std::to_string(state.step) +
                           "; the ensemble is saved in " + checkpoint->path() + "; continue with " +
                           (control.resume_command.empty() ? std::string("--resume") : control.resume_command));
  }

  // The chain (rank 0): every step's record from the checkpoint's order.
  if (root) records = checkpoint->load();
  std::vector<double> final_step{static_cast<double>(state.step)};
  broadcast_from_rank0(final_step);
  const long steps = std::lround(final_step[0]);
  std::vector<Eigen::MatrixXd> samples(static_cast<std::size_t>(p), Eigen::MatrixXd(steps, walkers));
  Eigen::MatrixXd log_posterior(steps, walkers);
  long accepted_moves = 0;
  std::vector<double> draws;  // predictive draws, K x p, broadcast
  const long kept = steps - m.discard;
  if (root) {
    if (records.size() < static_cast<std::size_t>(steps + 1))
      throw std::runtime_error("calibrate: the checkpoint " + checkpoint->path() + " lost steps");
    ChainSamples chain = chain_samples(records, steps, walkers, p);
    samples = std::move(chain.samples);
    log_posterior = std::move(chain.log_posterior);
    accepted_moves = chain.accepted_moves;
    // K draws spread evenly over the kept samples (step-major).
    const long total = kept * walkers;
    for (int d = 0; d < m.predictive_draws; ++d) {
      const long flat = (static_cast<long>(d) * total) / std::max(1, m.predictive_draws);
      const long st = m.discard + flat / walkers, w = flat % walkers;
      for (int k = 0; k < p; ++k) draws.push_back(samples[static_cast<std::size_t>(k)](st, w));
    }
  }
  broadcast_from_rank0(draws);

  // Posterior predictive: re-simulate the draws (fanned out).
  const int K = static_cast<int>(draws.size()) / std::max(1, p);  // draws
  std::vector<int> predictive_tasks(static_cast<std::size_t>(K));
  for (int d = 0; d < K; ++d) predictive_tasks[static_cast<std::size_t>(d)] = d;
  TaskFarmOptions farm;
  farm.label = "calibrate: posterior predictive";
  farm.progress_interval_s = control.progress_interval_s;
  const std::vector<TaskResult> predictive = run_task_farm(
      predictive_tasks,
      [&](int d) {
        std::vector<double> values(draws.begin() + d * p, draws.begin() + d * p + p_fit);
        const CalibrationResiduals fit = calibration_residuals(s, values);
        TaskResult r{d, fit.ok ? 0 : 1, fit.message, {}};
        for (std::size_t c = 0; c < curves && fit.ok; ++c)  // model values at the data times, curve after curve
          for (std::size_t i = 0; i < fit.residuals[c].size(); ++i)
            r.values.push_back(fit.residuals[c][i] + s.datasets[c].z[i]);
        return r;
      },
      {}, farm);
  std::vector<double> mixed_flag{mixed ? 1.0 : 0.0};
  broadcast_from_rank0(mixed_flag);
  CalibrationOutcome outcome{out, true, ""};
  if (m.target_ess > 0 && mixed_flag[0] == 0.0) {
    outcome.trusted = false;
    outcome.why = "the chain did not meet its target in " + std::to_string(steps) + " steps: " + progress;
  }
  if (!root) return outcome;
  remove_checkpoint(out);

  // Summaries over the kept steps.
  const ChainDiagnostics diagnostics = diagnose_chain(samples, accepted_moves, static_cast<int>(m.discard));
  std::vector<double> mean(p), sd(p), q025(p), q975(p), map(p);
  Eigen::Index best_step = 0, best_walker = 0;
  log_posterior.bottomRows(kept).maxCoeff(&best_step, &best_walker);
  best_step += m.discard;
  for (int k = 0; k < p; ++k) {
    const Eigen::MatrixXd tail = samples[static_cast<std::size_t>(k)].bottomRows(kept);
    std::vector<double> v(tail.data(), tail.data() + tail.size());
    mean[k] = tail.mean();
    sd[k] = std::sqrt((tail.array() - mean[k]).square().sum() / static_cast<double>(tail.size() - 1));
    q025[k] = quantile_of(v, 0.025);
    q975[k] = quantile_of(v, 0.975);
    map[k] = samples[static_cast<std::size_t>(k)](best_step, best_walker);
  }

  // The 99.73 % predictive band over the data times, without and with noise
  // (M noisy replicates per draw, each with the draw's noise sd).
  // All curves' points in one vector; first[c] is curve c's first point.
  std::vector<std::size_t> first(curves + 1, 0);
  for (std::size_t c = 0; c < curves; ++c) first[c + 1] = first[c] + s.datasets[c].t.size();
  const std::size_t n = first[curves];
  std::vector<std::vector<double>> model_curves;
  std::vector<std::vector<double>> point_sd;  // per draw, per point
  for (const TaskResult& r : predictive)
    if (r.status == 0) {
      model_curves.push_back(r.values);
      std::vector<double> sd_of_point(n);
      for (std::size_t c = 0; c < curves; ++c)
        for (std::size_t i = first[c]; i < first[c + 1]; ++i)
          sd_of_point[i] = m.sample_noise ? draws[static_cast<std::size_t>(r.index * p + p_fit) + c] : *known_sd;
      point_sd.push_back(std::move(sd_of_point));
    }
  std::vector<double> band_mean(n), band_lower(n), band_upper(n), noise_lower(n), noise_upper(n);
  constexpr int kReplicates = 25;
  constexpr double kLowerTail = 0.00135, kUpperTail = 0.99865;
  if (!model_curves.empty()) {
    boost::random::mt19937_64 engine(m.seed ^ 0x9e3779b97f4a7c15ull);
    boost::random::normal_distribution<double> gauss;
    std::vector<std::vector<double>> noisy(n);
    for (std::size_t c = 0; c < model_curves.size(); ++c)
      for (int j = 0; j < kReplicates; ++j)
        for (std::size_t i = 0; i < n; ++i) noisy[i].push_back(model_curves[c][i] + point_sd[c][i] * gauss(engine));
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<double> at(model_curves.size());
      double sum = 0;
      for (std::size_t c = 0; c < model_curves.size(); ++c) sum += (at[c] = model_curves[c][i]);
      band_mean[i] = sum / static_cast<double>(model_curves.size());
      band_lower[i] = quantile_of(at, kLowerTail);
      band_upper[i] = quantile_of(at, kUpperTail);
      noise_lower[i] = quantile_of(noisy[i], kLowerTail);
      noise_upper[i] = quantile_of(noisy[i], kUpperTail);
    }
  }

  io::Hdf5Writer h5(out);
  std::vector<double> chain;
  chain.reserve(static_cast<std::size_t>(steps * walkers * p));
  for (long st = 0; st < steps; ++st)
    for (int w = 0; w < walkers; ++w)
      for (int k = 0; k < p; ++k) chain.push_back(samples[static_cast<std::size_t>(k)](st, w));
  h5.write("/chain", chain, static_cast<std::size_t>(steps), static_cast<std::size_t>(walkers * p));
  h5.attribute("/chain", "shape", "steps x walkers x parameters = " + std::to_string(steps) + " x " +
                                      std::to_string(walkers) + " x " + std::to_string(p));
  h5.write("/log_posterior", log_posterior);
  h5.write("/posterior/names", names);
  h5.write("/posterior/mean", mean);
  h5.write("/posterior/sd", sd);
  h5.write("/posterior/q025", q025);
  h5.write("/posterior/q975", q975);
  h5.write("/posterior/map", map);
  h5.attribute("/posterior", "discarded_steps", static_cast<long long>(m.discard));
  h5.attribute("/posterior", "time_offset", s.offset_fitted() ? "sampled" : "profiled (best offset per proposal)");
  h5.attribute("/posterior", "noise_sd", m.sample_noise ? "sampled: " + m.noise_prior.describe()
                                                          : "known: " + format_number(*known_sd, 6) + " m");
  for (int k = 0; k < p_fit; ++k)
    h5.attribute("/posterior", "prior_" + names[static_cast<std::size_t>(k)], priors[static_cast<std::size_t>(k)].describe());
  h5.write("/diagnostics/acceptance_fraction", std::vector<double>{diagnostics.acceptance_fraction});
  auto as_vector = [](const Eigen::VectorXd& v) { return std::vector<double>(v.begin(), v.end()); };
  h5.write("/diagnostics/autocorrelation_time", as_vector(diagnostics.autocorrelation_time));
  h5.write("/diagnostics/effective_sample_size", as_vector(diagnostics.effective_sample_size));
  h5.write("/diagnostics/split_rhat", as_vector(diagnostics.split_rhat));
  h5.write("/diagnostics/nested_rhat", as_vector(diagnostics.nested_rhat));
  h5.attribute("/diagnostics", "warning", diagnostics.warning);
  h5.attribute("/diagnostics", "mixed", static_cast<long long>(outcome.trusted));
  h5.attribute("/diagnostics", "not_mixed_because", outcome.why);
  h5.attribute("/diagnostics", "target_ess", m.target_ess);
  h5.attribute("/diagnostics", "max_rhat", m.max_rhat);
  // Curve 0 at /predictive and /data, curve c at /predictive/c and /data/c.
  auto slice = [&](const std::vector<double>& v, std::size_t c) {
    return std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(first[c]),
                               v.begin() + static_cast<std::ptrdiff_t>(first[c + 1]));
  };
  for (std::size_t c = 0; c < curves; ++c) {
    const std::string g = "/predictive" + (c == 0 ? std::string() : "/" + std::to_string(c));
    h5.write(g + "/t", s.datasets[c].t);
    h5.write(g + "/mean", slice(band_mean, c));
    h5.write(g + "/lower", slice(band_lower, c));
    h5.write(g + "/upper", slice(band_upper, c));
    h5.write(g + "/lower_noise", slice(noise_lower, c));
    h5.write(g + "/upper_noise", slice(noise_upper, c));
    const std::string d = "/data" + (c == 0 ? std::string() : "/" + std::to_string(c));
    h5.write(d + "/t", s.datasets[c].t);
    h5.write(d + "/z", s.datasets[c].z);
  }
  h5.attribute("/predictive", "draws", static_cast<long long>(model_curves.size()));
  h5.attribute("/predictive", "coverage", 0.9973);
  write_study_provenance(h5, s.common);
  h5.attribute("/", "data_file", s.data_path);
  h5.attribute("/", "method", std::string("mcmc"));
  h5.attribute("/", "walkers", static_cast<long long>(walkers));
  h5.attribute("/", "steps", static_cast<long long>(steps));
  h5.attribute("/", "seed", static_cast<long long>(m.seed));
  h5.attribute("/", "calibration_fingerprint", s.fingerprint);
  h5.commit();

  if (!outcome.trusted)
    std::cerr << "calibrate: WARNING: the posterior is NOT VALID: " << outcome.why
              << " (written with /diagnostics mixed = 0; exit status 2)\n";
  std::cerr << "calibrate: posterior from " << walkers << " walkers x " << steps << " steps (first "
            << m.discard << " discarded); time offset "
            << (s.offset_fitted() ? "sampled" : "profiled (best offset for each proposal)") << "\n";
  for (int k = 0; k < p; ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    std::cerr << "  " << names[static_cast<std::size_t>(k)] << " = " << format_number(mean[k], 6) << " +- "
              << format_number(sd[k], 3) << " (sd); 95 % [" << format_number(q025[k], 6) << ", "
              << format_number(q975[k], 6) << "]; MAP " << format_number(map[k], 6) << "; tau "
              << format_number(diagnostics.autocorrelation_time[i], 3) << ", ESS "
              << format_number(diagnostics.effective_sample_size[i], 3) << ", R-hat "
              << format_number(diagnostics.split_rhat[i], 4) << ", nested R-hat "
              << format_number(diagnostics.nested_rhat[i], 4) << "\n";
  }
  std::cerr << "calibrate: acceptance " << format_number(diagnostics.acceptance_fraction, 3) << "\n";
  if (!diagnostics.warning.empty())
    std::cerr << "calibrate: WARNING: " << diagnostics.warning << "\n";

  std::cerr << "calibrate: wrote " << out << "\n";

  if (control.plot) {
    const std::string stem = out.substr(0, out.size() - 3);
    for (int k = 0; k < p; ++k) {  // traces: every walker
      io::LinePlot trace;
      trace.title = s.common.name + ": trace of " + names[static_cast<std::size_t>(k)] + " (all walkers)";
      trace.x_label = "step";
      trace.y_label = names[static_cast<std::size_t>(k)];
      for (int w = 0; w < walkers; ++w) {
        io::Series series;
        series.color = "#4060a0";
        series.line_width = 0.5;
        for (long st = 0; st < steps; ++st) {
          series.x.push_back(static_cast<double>(st + 1));
          series.y.push_back(samples[static_cast<std::size_t>(k)](st, w));
        }
        trace.series.push_back(std::move(series));
      }
      io::write_png_or_warn(trace, stem + "_trace_" + names[static_cast<std::size_t>(k)] + ".png", "calibrate", std::cerr);
    }
    std::vector<CornerParameter> shown;
    for (const std::string& name : names) shown.push_back(corner_parameter(name));
    io::write_png_or_warn(corner_plot(s.common.name + ": posterior, " + std::to_string(kept) + " steps x " +
                                          std::to_string(walkers) + " walkers after " + std::to_string(m.discard) +
                                          " burn-in steps",
                                      shown, samples, m.discard, mean, q025, q975),
                          stem + "_corner.png", "calibrate", std::cerr);
    for (std::size_t c = 0; c < curves && !model_curves.empty(); ++c) {
      io::LinePlot band;
      band.title = s.common.name + ": posterior predictive 99.73 % band of " + s.datasets[c].channel + " (" +
                   std::to_string(model_curves.size()) + " draws, curve " + std::to_string(c) + ")";
      band.x_label = "t (data clock) [s]";
      band.y_label = s.datasets[c].channel + " [mm]";
      auto mm = [](std::vector<double> v) {
        for (double& x : v) x *= 1000.0;
        return v;
      };
      band.bands.push_back({.label = "with measurement noise", .x = s.datasets[c].t, .lower = mm(slice(noise_lower, c)),
                            .upper = mm(slice(noise_upper, c)), .color = "#a0c0ff", .opacity = 0.4});
      band.bands.push_back({.label = "model only", .x = s.datasets[c].t, .lower = mm(slice(band_lower, c)),
                            .upper = mm(slice(band_upper, c)), .color = "#2040a0", .opacity = 0.5});
      band.series.push_back({.label = "data", .x = s.datasets[c].t, .y = mm(s.datasets[c].z),
                             .style = io::SeriesStyle::points, .color = "black", .line_width = 1.0});
      io::write_png_or_warn(band, stem + "_predictive" + (c == 0 ? std::string() : "_" + std::to_string(c)) + ".png",
                            "calibrate", std::cerr);
    }
  }
  return outcome;
}

}  // namespace rover::study
