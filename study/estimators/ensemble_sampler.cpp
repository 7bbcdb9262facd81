#include "study/estimators/ensemble_sampler.hpp"
#include "study/estimators/splitmix64.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_01.hpp>
#include <boost/random/uniform_int_distribution.hpp>

namespace rover::study {
namespace {

// The engine of walker `walker` at step `step`: a function of (seed, step,
// walker) only.
boost::random::mt19937_64 walker_engine(std::uint64_t seed, long step, Eigen::Index walker) {
  const std::uint64_t h = splitmix64(splitmix64(seed) ^ static_cast<std::uint64_t>(step));
  return boost::random::mt19937_64(splitmix64(h ^ static_cast<std::uint64_t>(walker)));
}

void check_options(const EnsembleState& state, const EnsembleOptions& options) {
  const Eigen::Index p = state.positions.cols();
  if (p < 1) throw std::invalid_argument("ensemble sampler: the state has no parameters");
  if (options.walkers % 2 != 0 || options.walkers < 2 * p)
    throw std::invalid_argument("ensemble sampler: walkers must be even and at least twice the " +
                                std::to_string(p) + " parameters (got " +
                                std::to_string(options.walkers) + ")");
  if (state.positions.rows() != options.walkers || state.log_density.size() != options.walkers)
    throw std::invalid_argument("ensemble sampler: the state has " +
                                std::to_string(state.positions.rows()) + " walkers, options say " +
                                std::to_string(options.walkers));
  if (!(options.stretch_scale > 1.0) || !std::isfinite(options.stretch_scale))
    throw std::invalid_argument("ensemble sampler: stretch_scale must be finite and > 1 (got " +
                                std::to_string(options.stretch_scale) + ")");
}

}  // namespace

Eigen::VectorXd evaluate_batch(const BatchLogDensity& log_density, const DesignMatrix& points) {
  Eigen::VectorXd values = log_density(points);
  if (values.size() != points.rows())
    throw std::runtime_error("log density callback returned " + std::to_string(values.size()) +
                             " values for " + std::to_string(points.rows()) + " points");
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    if (std::isnan(values[i])) values[i] = -std::numeric_limits<double>::infinity();
    if (values[i] == std::numeric_limits<double>::infinity())
      throw std::runtime_error("log density is +inf at batch row " + std::to_string(i));
  }
  return values;
}

EnsembleState initial_ensemble_state(const DesignMatrix& initial_positions,
                                     const BatchLogDensity& log_density) {
  if (initial_positions.rows() < 1 || initial_positions.cols() < 1)
    throw std::invalid_argument("ensemble sampler: empty initial positions");
  EnsembleState state;
  state.positions = initial_positions;
  state.log_density = evaluate_batch(log_density, initial_positions);
  for (Eigen::Index k = 0; k < state.log_density.size(); ++k)
    if (!std::isfinite(state.log_density[k]))
      throw std::invalid_argument("ensemble sampler: initial walker " + std::to_string(k) +
                                  " has a non-finite log density (outside the support or a "
                                  "failed model run)");
  state.step = 0;
  return state;
}

EnsembleState ensemble_step(const EnsembleState& state, const BatchLogDensity& log_density,
                            const EnsembleOptions& options, std::vector<bool>* accepted) {
  check_options(state, options);
  const Eigen::Index walkers = options.walkers;
  const Eigen::Index half = walkers / 2;
  const Eigen::Index p = state.positions.cols();
  const double a = options.stretch_scale;

  EnsembleState next = state;
  next.step = state.step + 1;
  if (accepted != nullptr) accepted->assign(static_cast<std::size_t>(walkers), false);

  DesignMatrix proposals(half, p);
  Eigen::VectorXd log_z(half), log_u(half);
  for (Eigen::Index moving = 0; moving < 2; ++moving) {
    const Eigen::Index first = moving * half;          // walkers moved now
    const Eigen::Index partners = (1 - moving) * half;  // the other half, as it is now
    for (Eigen::Index i = 0; i < half; ++i) {
      const Eigen::Index k = first + i;
      auto engine = walker_engine(options.seed, state.step, k);
      const Eigen::Index j =
          partners + boost::random::uniform_int_distribution<Eigen::Index>(0, half - 1)(engine);
      boost::random::uniform_01<double> uniform;
      // z = ((a - 1) u + 1)^2 / a has density proportional to 1/sqrt(z) on [1/a, a].
      const double root_z = ((a - 1.0) * uniform(engine) + 1.0) / std::sqrt(a);
      const double z = root_z * root_z;
      log_z[i] = std::log(z);
      log_u[i] = std::log(uniform(engine));  // log 0 = -inf: accepted unless the target is -inf
      proposals.row(i) = next.positions.row(j) + z * (next.positions.row(k) - next.positions.row(j));
    }
    const Eigen::VectorXd proposal_log_density = evaluate_batch(log_density, proposals);
    for (Eigen::Index i = 0; i < half; ++i) {
      const Eigen::Index k = first + i;
      const double log_ratio = static_cast<double>(p - 1) * log_z[i] + proposal_log_density[i] -
                               next.log_density[k];
      if (log_u[i] < log_ratio) {  // strict: a -inf proposal is never accepted
        next.positions.row(k) = proposals.row(i);
        next.log_density[k] = proposal_log_density[i];
        if (accepted != nullptr) (*accepted)[static_cast<std::size_t>(k)] = true;
      }
    }
  }
  return next;
}

EnsembleChain run_ensemble(const EnsembleState& start, const BatchLogDensity& log_density,
                           const EnsembleOptions& options, long steps) {
  if (steps < 0) throw std::invalid_argument("ensemble sampler: negative number of steps");
  check_options(start, options);
  const Eigen::Index p = start.positions.cols();
  const auto rows = static_cast<Eigen::Index>(steps);
  EnsembleChain chain;
  chain.samples.assign(static_cast<std::size_t>(p), Eigen::MatrixXd(rows, options.walkers));
  chain.log_density.resize(rows, options.walkers);
  chain.final_state = start;
  std::vector<bool> accepted;
  for (Eigen::Index s = 0; s < rows; ++s) {
    chain.final_state = ensemble_step(chain.final_state, log_density, options, &accepted);
    for (Eigen::Index q = 0; q < p; ++q)
      chain.samples[static_cast<std::size_t>(q)].row(s) = chain.final_state.positions.col(q).transpose();
    chain.log_density.row(s) = chain.final_state.log_density.transpose();
    for (bool moved : accepted) chain.accepted_moves += moved ? 1 : 0;
  }
  return chain;
}

}  // namespace rover::study
