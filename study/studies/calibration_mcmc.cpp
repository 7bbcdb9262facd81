// See calibration_mcmc.hpp.
#include "study/studies/calibration_lack_of_fit.hpp"
#include "study/studies/calibration_mcmc.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <numbers>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>

#include "io/checkpoint.hpp"
#include "study/estimators/ensemble_sampler.hpp"
#include "study/estimators/independence_sampler.hpp"
#include "study/runtime/rank0_broadcast.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/runtime/task_farm.hpp"
#include "study/studies/report_number.hpp"

namespace rover::study {
namespace {

constexpr double kNegativeInfinity = -std::numeric_limits<double>::infinity();
// The chains' target is checked every this many steps past the burn-in.
constexpr long kIndependenceCheckInterval = 10;
constexpr long kEnsembleCheckInterval = 50;
// The independence sampler's proposal: Student-t with these degrees of freedom.
constexpr double kProposalDegreesOfFreedom = 4.0;
// The ensemble's walkers start this many standard errors around the fit.
constexpr double kEnsembleBallStandardErrors = 0.1;
// The 99.73 % predictive band (three sd of a normal), with this many noise
// replicates per draw.
constexpr double kLowerTail = 0.00135, kUpperTail = 0.99865;
constexpr int kNoiseReplicates = 25;

// Sample quantile with linear interpolation between order statistics
// (Hyndman & Fan 1996, type 7) of an unsorted copy.
double quantile_of(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const double h = p * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

// The sampled parameters and their coordinates: u = log10 x for a log-scale
// fitted parameter and for each noise sd, u = x otherwise. The sampler works
// in u; its density carries the Jacobian |dx/du| = x ln 10 of each log10.
struct PosteriorSpace {
  std::vector<std::string> names;
  std::vector<Distribution> priors;   // the fitted parameters'
  std::vector<double> lower, upper;   // every sampled parameter's support (natural units)
  std::vector<bool> log10_scale;      // every sampled parameter's
  std::size_t fitted = 0, curves = 0;
  std::optional<double> known_noise_sd;

  std::size_t size() const { return names.size(); }
  double natural(std::size_t k, double u) const { return log10_scale[k] ? std::pow(10.0, u) : u; }
  double sampling(std::size_t k, double x) const { return log10_scale[k] ? std::log10(x) : x; }
};

PosteriorSpace posterior_space(const CalibrationStudy& s) {
  PosteriorSpace space;
  space.fitted = s.fit.size();
  space.curves = s.datasets.size();
  for (const FitParameter& f : s.fit) {
    space.names.push_back(f.name);
    space.priors.push_back(f.prior);
    space.lower.push_back(std::max(f.lower, f.prior.support_lower()));
    space.upper.push_back(std::min(f.upper, f.prior.support_upper()));
    space.log10_scale.push_back(f.log_scale);
  }
  if (!s.mcmc.sample_noise) {
    space.known_noise_sd = s.mcmc.known_noise_sd_m;
    return space;
  }
  for (std::size_t k = 0; k < space.curves; ++k) {
    space.names.push_back(space.curves == 1 ? "noise_sd" : "noise_sd[" + std::to_string(k) + "]");
    space.lower.push_back(s.mcmc.noise_prior.support_lower());
    space.upper.push_back(s.mcmc.noise_prior.support_upper());
    space.log10_scale.push_back(true);
  }
  return space;
}

// The log posterior in sampling coordinates at u; -inf outside the support
// without a simulation.
double log_density_at(const CalibrationStudy& s, const PosteriorSpace& space, const Eigen::VectorXd& u) {
  Eigen::VectorXd theta(u.size());
  double log_jacobian = 0.0;
  for (std::size_t k = 0; k < space.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    theta[i] = space.natural(k, u[i]);
    if (!(theta[i] >= space.lower[k] && theta[i] <= space.upper[k])) return kNegativeInfinity;
    if (space.log10_scale[k]) log_jacobian += std::log(theta[i] * std::numbers::ln10);
  }
  const double lp = calibration_log_density(
      space.priors, s.mcmc.noise_prior, space.known_noise_sd, space.curves, theta,
      [&](const std::vector<double>& values) {
        CalibrationResiduals fit = calibration_residuals(s, values);
        return fit.ok ? std::optional<std::vector<std::vector<double>>>(std::move(fit.residuals)) : std::nullopt;
      });
  return lp + log_jacobian;
}

// The batch density of a step: one task farm over all ranks, the values
// broadcast from rank 0 so every rank holds the same state. A signal stops
// the farm; `interrupted` is then set on every rank and the values are void.
BatchLogDensity parallel_log_density(const CalibrationStudy& s, const PosteriorSpace& space, bool& interrupted) {
  return [&s, &space, &interrupted](const DesignMatrix& points) {
    std::vector<int> tasks(static_cast<std::size_t>(points.rows()));
    for (std::size_t i = 0; i < tasks.size(); ++i) tasks[i] = static_cast<int>(i);
    TaskFarmOptions farm;
    farm.progress = nullptr;
    farm.stop = &InterruptGuard::flag();
    const std::vector<TaskResult> results = run_task_farm(
        tasks, [&](int i) { return TaskResult{i, 0, "", {log_density_at(s, space, points.row(i).transpose())}}; },
        {}, farm);
    std::vector<double> values(tasks.size(), kNegativeInfinity);
    for (const TaskResult& r : results)
      if (r.status == 0 && !r.values.empty()) values[static_cast<std::size_t>(r.index)] = r.values[0];
    values.push_back(results.size() == tasks.size() ? 0.0 : 1.0);  // rank 0 saw a stop
    broadcast_from_rank0(values);
    interrupted = interrupted || values.back() != 0.0;
    values.pop_back();
    return Eigen::Map<const Eigen::VectorXd>(values.data(), points.rows()).eval();
  };
}

// The noise sd of each curve at the start values (the RMS of its residuals) and its count.
struct CurveNoise {
  std::vector<double> sd, points;
};
CurveNoise noise_at(const CalibrationStudy& s, const std::vector<double>& values) {
  CurveNoise noise;
  const CalibrationResiduals fit = calibration_residuals(s, values);
  for (std::size_t c = 0; c < s.datasets.size(); ++c) {
    double ss = 0.0;
    const std::size_t n = fit.ok ? fit.residuals[c].size() : s.datasets[c].t.size();
    for (std::size_t i = 0; fit.ok && i < n; ++i) ss += fit.residuals[c][i] * fit.residuals[c][i];
    noise.sd.push_back(fit.ok ? std::sqrt(ss / static_cast<double>(n)) : s.mcmc.noise_prior.mean());
    noise.points.push_back(static_cast<double>(n));
  }
  return noise;
}

// The Laplace approximation of the posterior in sampling coordinates: the fit
// and its covariance (through the Jacobian of the log10 maps), each noise sd
// with var(log10 s) = 1 / (2 n ln(10)^2).
StudentTProposal laplace_proposal(const CalibrationStudy& s, const PosteriorSpace& space, const McmcStart& start) {
  const auto p = static_cast<Eigen::Index>(space.size()), fitted = static_cast<Eigen::Index>(space.fitted);
  StudentTProposal q{Eigen::VectorXd(p), Eigen::MatrixXd::Zero(p, p), kProposalDegreesOfFreedom};
  Eigen::VectorXd du_dx(fitted);
  for (Eigen::Index k = 0; k < fitted; ++k) {
    const auto i = static_cast<std::size_t>(k);
    q.mean[k] = space.sampling(i, start.values[i]);
    du_dx[k] = space.log10_scale[i] ? 1.0 / (start.values[i] * std::numbers::ln10) : 1.0;
  }
  q.scale.topLeftCorner(fitted, fitted) = du_dx.asDiagonal() * start.covariance * du_dx.asDiagonal();
  if (space.known_noise_sd) return q;
  const CurveNoise noise = noise_at(s, start.values);
  for (std::size_t c = 0; c < space.curves; ++c) {
    const auto i = fitted + static_cast<Eigen::Index>(c);
    q.mean[i] = std::log10(noise.sd[c]);
    q.scale(i, i) = 1.0 / (2.0 * noise.points[c] * std::numbers::ln10 * std::numbers::ln10);
  }
  return q;
}

// The ensemble's walkers: a ball of kEnsembleBallStandardErrors around the
// centre (the proposal's mean and scale), inside the support.
DesignMatrix ensemble_ball(const PosteriorSpace& space, const StudentTProposal& around, int walkers,
                           std::uint64_t seed) {
  constexpr int kTries = 100;
  boost::random::mt19937_64 engine(seed);
  boost::random::normal_distribution<double> gauss;
  DesignMatrix positions(walkers, static_cast<Eigen::Index>(space.size()));
  for (int w = 0; w < walkers; ++w)
    for (std::size_t k = 0; k < space.size(); ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      const double centre = around.mean[i];
      const double spread = kEnsembleBallStandardErrors * std::sqrt(around.scale(i, i));
      double u = centre + spread * gauss(engine);
      for (int tries = 0; tries < kTries && !(space.natural(k, u) > space.lower[k] && space.natural(k, u) < space.upper[k]); ++tries)
        u = centre + spread * gauss(engine);
      positions(w, i) = space.natural(k, u) > space.lower[k] && space.natural(k, u) < space.upper[k] ? u : centre;
    }
  return positions;
}

// The proposal around the start; without a converged fit, a diagonal one
// from the initial values and a fiftieth of each support's width.
StudentTProposal starting_proposal(const CalibrationStudy& s, const PosteriorSpace& space, const McmcStart& start) {
  if (!start.values.empty()) return laplace_proposal(s, space, start);
  McmcStart initial;
  const auto fitted = static_cast<Eigen::Index>(space.fitted);
  initial.covariance = Eigen::MatrixXd::Zero(fitted, fitted);
  for (std::size_t k = 0; k < space.fitted; ++k) {
    initial.values.push_back(s.fit[k].initial);
    const double width = s.fit[k].log_scale ? s.fit[k].initial : s.fit[k].upper - s.fit[k].lower;
    initial.covariance(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k)) = std::pow(0.02 * width, 2);
  }
  return laplace_proposal(s, space, initial);
}

// ---- The chain: stepping, checkpoint, progress and target ------------------

// A step's state as a checkpoint record: positions (row-major), log
// densities, then the accepted moves of the step.
struct StepRecord {
  static io::TaskRecord from(const EnsembleState& state, long accepted) {
    io::TaskRecord r;
    r.index = static_cast<int>(state.step);
    for (Eigen::Index c = 0; c < state.positions.rows(); ++c)
      for (Eigen::Index k = 0; k < state.positions.cols(); ++k) r.values.push_back(state.positions(c, k));
    r.values.insert(r.values.end(), state.log_density.begin(), state.log_density.end());
    r.values.push_back(static_cast<double>(accepted));
    return r;
  }
  static EnsembleState state(const std::vector<double>& v, long step, int chains, int p) {
    EnsembleState state;
    state.step = step;
    state.positions.resize(chains, p);
    state.log_density.resize(chains);
    for (int c = 0; c < chains; ++c) {
      for (int k = 0; k < p; ++k) state.positions(c, k) = v[static_cast<std::size_t>(c * p + k)];
      state.log_density[c] = v[static_cast<std::size_t>(chains * p + c)];
    }
    return state;
  }
};

// Records 1 .. steps as per-parameter steps x chains matrices (sampling
// coordinates), the log posterior and the accepted moves.
struct ChainSamples {
  std::vector<Eigen::MatrixXd> samples;
  Eigen::MatrixXd log_posterior;
  long accepted_moves = 0;
};
ChainSamples chain_samples(const std::vector<io::TaskRecord>& records, long steps, int chains, int p) {
  ChainSamples out{std::vector<Eigen::MatrixXd>(static_cast<std::size_t>(p), Eigen::MatrixXd(steps, chains)),
                   Eigen::MatrixXd(steps, chains), 0};
  for (long step = 1; step <= steps; ++step) {
    const io::TaskRecord& r = records[static_cast<std::size_t>(step)];
    const EnsembleState state = StepRecord::state(r.values, step, chains, p);
    for (int k = 0; k < p; ++k) out.samples[static_cast<std::size_t>(k)].row(step - 1) = state.positions.col(k).transpose();
    out.log_posterior.row(step - 1) = state.log_density.transpose();
    out.accepted_moves += std::lround(r.values.back());
  }
  return out;
}

// Whether the chain so far meets the study's target, and a line saying how far it is.
bool target_met(const ChainDiagnostics& d, const McmcSettings& m, std::string* progress) {
  const double ess = d.effective_sample_size.size() ? d.effective_sample_size.minCoeff() : 0.0;
  const double rhat = d.nested_rhat.size() ? d.nested_rhat.maxCoeff() : INFINITY;
  *progress = "smallest effective sample size " + format_number(ess, 3) + " (target " + format_number(m.target_ess, 3) +
              "), largest nested R-hat " + format_number(rhat, 5) + " (target < " + format_number(m.max_rhat, 5) + ")";
  return ess >= m.target_ess && rhat < m.max_rhat;
}

// One sampler, stepped in lockstep on every rank.
struct Sampler {
  McmcSampler kind;
  StudentTProposal proposal;  // independence: the proposal; ensemble: the ball's centre and scale
  int chains = 0;
  std::uint64_t seed = 1;

  long check_interval() const {
    return kind == McmcSampler::independence ? kIndependenceCheckInterval : kEnsembleCheckInterval;
  }
  EnsembleState initial(const PosteriorSpace& space, const BatchLogDensity& batch) const {
    if (kind == McmcSampler::independence)
      return initial_independence_state(proposal, batch, {.chains = chains, .seed = seed});
    return initial_ensemble_state(ensemble_ball(space, proposal, chains, seed), batch);
  }
  EnsembleState step(const EnsembleState& state, const BatchLogDensity& batch, std::vector<bool>* accepted) const {
    if (kind == McmcSampler::independence)
      return independence_step(state, proposal, batch, {.chains = chains, .seed = seed}, accepted);
    return ensemble_step(state, batch, {.walkers = chains, .stretch_scale = 2.0, .seed = seed}, accepted);
  }
};

// The chain's records on rank 0 (record k: the state after step k) and
// whether its target was met.
struct ChainRun {
  std::vector<io::TaskRecord> records;
  long steps = 0;
  bool mixed = false;
  bool interrupted = false;
  std::string progress;
};

// The state to continue from: the checkpoint's last contiguous step
// (--resume), else a fresh start, recorded as step 0.
EnsembleState starting_state(const Sampler& sampler, const PosteriorSpace& space, const BatchLogDensity& batch,
                             std::optional<io::ResultCheckpoint>& checkpoint, ChainRun& run, bool resume) {
  std::vector<double> saved;
  if (checkpoint) {
    if (resume) {
      run.records = checkpoint->load();
      report_dropped_checkpoint_bytes(*checkpoint, "calibrate", "chain steps");
    }
    std::size_t contiguous = 0;
    while (contiguous < run.records.size() && run.records[contiguous].index == static_cast<int>(contiguous)) ++contiguous;
    run.records.resize(contiguous);
    if (!run.records.empty()) {
      saved = run.records.back().values;
      saved.push_back(static_cast<double>(run.records.back().index));
    }
  }
  broadcast_from_rank0(saved);
  const int p = static_cast<int>(space.size());
  if (!saved.empty()) {
    if (checkpoint)
      std::cerr << "calibrate: resuming the chains after step " << std::lround(saved.back()) << " from "
                << checkpoint->path() << "\n";
    return StepRecord::state(saved, std::lround(saved.back()), sampler.chains, p);
  }
  EnsembleState state = sampler.initial(space, batch);
  if (checkpoint) {
    run.records.push_back(StepRecord::from(state, 0));
    checkpoint->add(run.records.back());
  }
  return state;
}

// Rank 0, after a step: the target check and the progress line.
void after_step(const McmcSettings& m, const Sampler& sampler, long discard, int p, ChainRun& run,
                long step) {
  if (m.target_ess <= 0 || step < discard + sampler.check_interval() || step % sampler.check_interval() != 0) return;
  const ChainSamples chain = chain_samples(run.records, step, sampler.chains, p);
  run.mixed = target_met(diagnose_chain(chain.samples, chain.accepted_moves, static_cast<int>(discard), {}, m.max_rhat),
                         m, &run.progress);
  std::cerr << "calibrate: step " << step << " (at most " << m.steps << "): " << run.progress << "\n";
}

ChainRun run_chain(const CalibrationStudy& s, const StudyRunOptions& control, const PosteriorSpace& space,
                   const Sampler& sampler, long discard, const std::string& out) {
  const bool root = world_rank() == 0;
  const McmcSettings& m = s.mcmc;
  const int p = static_cast<int>(space.size());
  bool interrupted = false;
  const BatchLogDensity batch = parallel_log_density(s, space, interrupted);
  io::CheckpointPolicy policy = control.checkpoint;
  policy.every_records = 1;
  std::optional<io::ResultCheckpoint> checkpoint;
  if (root) checkpoint.emplace(out, s.fingerprint, policy);
  ChainRun run;
  EnsembleState state = starting_state(sampler, space, batch, checkpoint, run, control.resume);
  // Resumed chains may have met their target at the saved step (a signal
  // during the predictive draws): checked as that step was, so a resumed
  // study stops where the uninterrupted one did.
  std::vector<double> met_when_saved{0.0};
  if (root && state.step > 0) {
    after_step(m, sampler, discard, p, run, state.step);
    met_when_saved[0] = run.mixed ? 1.0 : 0.0;
  }
  broadcast_from_rank0(met_when_saved);
  std::vector<bool> accepted;
  while (met_when_saved[0] == 0.0 && state.step < m.steps && !interrupted) {
    EnsembleState next = sampler.step(state, batch, &accepted);
    if (interrupted) break;  // the step is incomplete: not recorded
    state = std::move(next);
    if (root) {
      run.records.push_back(StepRecord::from(state, std::count(accepted.begin(), accepted.end(), true)));
      checkpoint->add(run.records.back());
      after_step(m, sampler, discard, p, run, state.step);
    }
    std::vector<double> stop{root && InterruptGuard::flag().load() ? 1.0 : 0.0, run.mixed ? 1.0 : 0.0};
    broadcast_from_rank0(stop);
    interrupted = stop[0] != 0.0 && state.step < m.steps;
    if (stop[1] != 0.0) break;  // the target is met
  }
  if (root) checkpoint->save();
  run.steps = state.step;
  run.interrupted = interrupted;
  if (interrupted && root)  // rank 0 reports; the other ranks return
    throw StudyInterrupted("calibrate: interrupted after step " + std::to_string(state.step) +
                           "; the chains are saved in " + checkpoint->path() + "; continue with " +
                           (control.resume_command.empty() ? std::string("--resume") : control.resume_command));
  return run;
}

// ---- Summaries and the predictive band -------------------------------------

PosteriorSummary summarise(const std::vector<Eigen::MatrixXd>& samples, const Eigen::MatrixXd& log_posterior,
                           long discard) {
  PosteriorSummary out;
  const long kept = log_posterior.rows() - discard;
  Eigen::Index best_step = 0, best_chain = 0;
  log_posterior.bottomRows(kept).maxCoeff(&best_step, &best_chain);
  for (const Eigen::MatrixXd& x : samples) {
    const Eigen::MatrixXd tail = x.bottomRows(kept);
    const std::vector<double> v(tail.data(), tail.data() + tail.size());
    const double mean = tail.mean();
    out.mean.push_back(mean);
    out.sd.push_back(std::sqrt((tail.array() - mean).square().sum() / static_cast<double>(tail.size() - 1)));
    out.q025.push_back(quantile_of(v, 0.025));
    out.q975.push_back(quantile_of(v, 0.975));
    out.map.push_back(x(discard + best_step, best_chain));
  }
  return out;
}

// Draws spread evenly over the kept samples (step-major), broadcast: the p
// sampled parameters (natural units) of each draw.
std::vector<std::vector<double>> predictive_draws(const CalibrationPosterior& posterior, int count, std::size_t p) {
  std::vector<double> flat;
  if (world_rank() == 0) {
    const long kept = posterior.steps - posterior.discard, total = kept * posterior.chains;
    for (int d = 0; d < count; ++d) {
      const long at = static_cast<long>(d) * total / std::max(1, count);
      const long step = posterior.discard + at / posterior.chains, chain = at % posterior.chains;
      for (const Eigen::MatrixXd& x : posterior.samples) flat.push_back(x(step, chain));
    }
  }
  broadcast_from_rank0(flat);
  std::vector<std::vector<double>> draws;
  for (std::size_t at = 0; at + p <= flat.size(); at += p)
    draws.emplace_back(flat.begin() + static_cast<std::ptrdiff_t>(at), flat.begin() + static_cast<std::ptrdiff_t>(at + p));
  return draws;
}

// The model at each draw, at every curve's data times (curve after curve);
// the failed draws left out. Collective.
struct PredictiveRuns {
  std::vector<std::vector<double>> model;     // per draw that ran
  std::vector<std::vector<double>> noise_sd;  // per draw that ran, per curve
};
PredictiveRuns run_predictive(const CalibrationStudy& s, const std::vector<std::vector<double>>& draws,
                              const StudyRunOptions& control) {
  const std::size_t fitted = s.fit.size(), curves = s.datasets.size();
  std::vector<int> tasks(draws.size());
  for (std::size_t d = 0; d < draws.size(); ++d) tasks[d] = static_cast<int>(d);
  TaskFarmOptions farm;
  farm.label = "calibrate: posterior predictive";
  farm.progress_interval_s = control.progress_interval_s;
  farm.stop = &InterruptGuard::flag();
  const std::vector<TaskResult> results = run_task_farm(
      tasks,
      [&](int d) {
        const std::vector<double>& draw = draws[static_cast<std::size_t>(d)];
        const CalibrationResiduals fit = calibration_residuals(s, std::vector<double>(draw.begin(), draw.begin() + static_cast<std::ptrdiff_t>(fitted)));
        TaskResult r{d, fit.ok ? 0 : 1, fit.message, {}};
        for (std::size_t c = 0; c < curves && fit.ok; ++c)
          for (std::size_t i = 0; i < fit.residuals[c].size(); ++i) r.values.push_back(fit.residuals[c][i] + s.datasets[c].z[i]);
        return r;
      },
      {}, farm);
  PredictiveRuns runs;
  for (const TaskResult& r : results) {
    if (r.status != 0) continue;
    const std::vector<double>& draw = draws[static_cast<std::size_t>(r.index)];
    runs.model.push_back(r.values);
    std::vector<double> sd(curves, s.mcmc.known_noise_sd_m);
    for (std::size_t c = 0; c < curves && s.mcmc.sample_noise; ++c) sd[c] = draw[fitted + c];
    runs.noise_sd.push_back(std::move(sd));
  }
  return runs;
}

// The 99.73 % band of each curve, without and with measurement noise
// (kNoiseReplicates Gaussian replicates per draw, each with its noise sd).
std::vector<PredictiveBand> predictive_bands(const CalibrationStudy& s, const PredictiveRuns& runs, std::uint64_t seed) {
  std::vector<PredictiveBand> bands;
  boost::random::mt19937_64 engine(seed ^ 0x9e3779b97f4a7c15ull);
  boost::random::normal_distribution<double> gauss;
  std::size_t first = 0;
  for (std::size_t c = 0; c < s.datasets.size(); ++c) {
    PredictiveBand band;
    band.t = s.datasets[c].t;
    for (std::size_t i = first; i < first + s.datasets[c].t.size() && !runs.model.empty(); ++i) {
      std::vector<double> at, noisy;
      for (std::size_t d = 0; d < runs.model.size(); ++d) {
        at.push_back(runs.model[d][i]);
        for (int j = 0; j < kNoiseReplicates; ++j) noisy.push_back(runs.model[d][i] + runs.noise_sd[d][c] * gauss(engine));
      }
      double sum = 0.0;
      for (double v : at) sum += v;
      band.mean.push_back(sum / static_cast<double>(at.size()));
      band.lower.push_back(quantile_of(at, kLowerTail));
      band.upper.push_back(quantile_of(at, kUpperTail));
      band.lower_noise.push_back(quantile_of(noisy, kLowerTail));
      band.upper_noise.push_back(quantile_of(noisy, kUpperTail));
    }
    first += s.datasets[c].t.size();
    bands.push_back(std::move(band));
  }
  return bands;
}

// A max_rhat is shown to this many digits, so that 1.0001 is never "1".
constexpr int kMaxRhatDigits = 8;

// Without a target the chains run a fixed length and are judged by it: one
// too short for its autocorrelation time, that never moves, or whose nested
// R-hat reaches max_rhat has no intervals to trust. Why, or empty.
std::string fixed_length_chain_problem(const ChainDiagnostics& d, const McmcSettings& m, long steps,
                                       const std::vector<std::string>& names) {
  const std::string ran = "target_ess 0 ran a fixed " + std::to_string(steps) + " steps";
  if (d.chain_too_short) return ran + ", too few: " + d.warning;
  std::string unmixed;
  for (Eigen::Index q = 0; q < d.nested_rhat.size(); ++q)
    if (!(d.nested_rhat[q] < m.max_rhat))
      unmixed += (unmixed.empty() ? "" : ", ") + names[static_cast<std::size_t>(q)] + " " +
                 format_number(d.nested_rhat[q], 5);
  if (unmixed.empty()) return "";
  return ran + " and the walkers have not mixed: nested R-hat " + unmixed + " (max_rhat " +
         format_number(m.max_rhat, kMaxRhatDigits) + ")";
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

std::string mcmc_start_outside_priors(const CalibrationStudy& s, const McmcStart& start) {
  const PosteriorSpace space = posterior_space(s);
  const StudentTProposal centre = starting_proposal(s, space, start);
  const std::string at = start.values.empty() ? "initial value" : "least-squares estimate";
  for (std::size_t k = 0; k < space.size(); ++k) {
    // A fitted value as the fit left it (a log10 and back could step off a bound).
    const double value = k >= space.fitted ? space.natural(k, centre.mean[static_cast<Eigen::Index>(k)])
                         : start.values.empty() ? s.fit[k].initial
                                                : start.values[k];
    if (value >= space.lower[k] && value <= space.upper[k]) continue;
    const std::string support = "[" + format_number(space.lower[k], 6) + ", " + format_number(space.upper[k], 6) + "]";
    if (k < space.fitted)
      return "the " + at + " " + space.names[k] + " = " + format_number(value, 6) + " lies outside priors." +
             space.names[k] + " (" + space.priors[k].describe() + ", within bounds." + space.names[k] + ": " +
             support + "): the data and the prior disagree, and the chains, which start around the fit, have no "
             "point of positive posterior density to start from; widen the prior, or check the data and the scenario";
    const CalibrationDataset& d = s.datasets[k - space.fitted];
    return "the noise sd the chains start from, the residual RMS of " + d.path + " at the " + at + ", " +
           format_number(value, 6) + " m, lies outside the support " + support + " m of mcmc.noise_sd (" +
           s.mcmc.noise_prior.describe() + "): the data and the prior disagree; widen the noise prior, or check "
           "the data and the scenario";
  }
  return "";
}

CalibrationPosterior run_calibration_mcmc(const CalibrationStudy& s, const StudyRunOptions& control,
                                          const McmcStart& start) {
  const std::string& out = control.results_path;
  const PosteriorSpace space = posterior_space(s);
  CalibrationPosterior posterior;
  posterior.names = space.names;
  const bool independence = s.mcmc.sampler == McmcSampler::independence && !start.values.empty();
  const Sampler sampler{independence ? McmcSampler::independence : McmcSampler::ensemble,
                        starting_proposal(s, space, start), s.mcmc.walkers, s.mcmc.seed};
  posterior.sampler = independence ? "independence" : "ensemble";
  posterior.chains = s.mcmc.walkers;
  posterior.discard = mcmc_discard(s.mcmc, sampler.kind);
  ChainRun run = run_chain(s, control, space, sampler, posterior.discard, out);
  posterior.steps = run.steps;
  if (run.interrupted) {  // a rank other than 0: rank 0 has thrown
    posterior.mixed = false;
    posterior.not_mixed_because = "interrupted";
    return posterior;
  }
  std::vector<double> mixed{run.mixed ? 1.0 : 0.0};
  broadcast_from_rank0(mixed);
  posterior.mixed = s.mcmc.target_ess <= 0 || mixed[0] != 0.0;
  if (!posterior.mixed)
    posterior.not_mixed_because = "the chains did not meet their target in " + std::to_string(run.steps) +
                                  " steps: " + run.progress;
  if (world_rank() == 0) {
    ChainSamples chain = chain_samples(run.records, run.steps, posterior.chains, static_cast<int>(space.size()));
    for (std::size_t k = 0; k < space.size(); ++k)
      posterior.samples.push_back(chain.samples[k].unaryExpr([&](double u) { return space.natural(k, u); }));
    posterior.log_posterior = std::move(chain.log_posterior);
    posterior.diagnostics = diagnose_chain(chain.samples, chain.accepted_moves, static_cast<int>(posterior.discard),
                                           space.names, s.mcmc.max_rhat);
    posterior.summary = summarise(posterior.samples, posterior.log_posterior, posterior.discard);
    if (s.mcmc.target_ess <= 0) {
      posterior.not_mixed_because = fixed_length_chain_problem(posterior.diagnostics, s.mcmc, run.steps, space.names);
      posterior.mixed = posterior.not_mixed_because.empty();
    }
  }
  const PredictiveRuns runs = run_predictive(s, predictive_draws(posterior, s.mcmc.predictive_draws, space.size()), control);
  if (world_rank() != 0) return posterior;
  posterior.predictive_draws = static_cast<int>(runs.model.size());
  posterior.predictive = predictive_bands(s, runs, s.mcmc.seed);
  const std::vector<double> map(posterior.summary.map.begin(),
                                posterior.summary.map.begin() + static_cast<std::ptrdiff_t>(s.fit.size()));
  LackOfFit lack = lack_of_fit_at(s, map, s.mcmc.sample_noise ? 0.0 : s.mcmc.known_noise_sd_m);
  posterior.residual_lag1 = std::move(lack.residual_lag1);
  posterior.residual_rms_m = std::move(lack.residual_rms_m);
  posterior.lack_of_fit = std::move(lack.reason);
  return posterior;
}

}  // namespace rover::study
