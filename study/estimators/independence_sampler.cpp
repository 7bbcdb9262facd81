// See independence_sampler.hpp.
#include "study/estimators/independence_sampler.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <boost/math/special_functions/gamma.hpp>
#include <boost/random/chi_squared_distribution.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <boost/random/uniform_01.hpp>

#include "study/estimators/splitmix64.hpp"

namespace rover::study {
namespace {

constexpr double kNegativeInfinity = -std::numeric_limits<double>::infinity();
// Rounds of fresh draws for a chain whose initial draw has zero density.
constexpr int kInitialRounds = 100;

boost::random::mt19937_64 chain_engine(std::uint64_t seed, long step, Eigen::Index chain) {
  const std::uint64_t h = splitmix64(splitmix64(seed ^ 0x5bd1e995u) ^ static_cast<std::uint64_t>(step));
  return boost::random::mt19937_64(splitmix64(h ^ static_cast<std::uint64_t>(chain)));
}

// The Cholesky factor of the proposal's scale, checked.
Eigen::LLT<Eigen::MatrixXd> checked_factor(const StudentTProposal& proposal) {
  const Eigen::Index p = proposal.mean.size();
  if (p < 1 || proposal.scale.rows() != p || proposal.scale.cols() != p)
    throw std::invalid_argument("Student-t proposal: the scale is " + std::to_string(proposal.scale.rows()) + " x " +
                                std::to_string(proposal.scale.cols()) + " for a mean of " + std::to_string(p));
  if (!(proposal.degrees_of_freedom > 0.0) || !std::isfinite(proposal.degrees_of_freedom))
    throw std::invalid_argument("Student-t proposal: degrees of freedom must be finite and > 0");
  Eigen::LLT<Eigen::MatrixXd> llt(proposal.scale);
  if (llt.info() != Eigen::Success || !proposal.scale.allFinite())
    throw std::invalid_argument("Student-t proposal: the scale is not positive definite");
  return llt;
}

// One draw of t_nu(mean, L L^T) and the log of a uniform, from one engine.
struct ChainDraw {
  Eigen::VectorXd point;
  double log_uniform = 0.0;
};
ChainDraw draw_one(const StudentTProposal& proposal, const Eigen::MatrixXd& lower, std::uint64_t seed, long step,
                   Eigen::Index chain) {
  auto engine = chain_engine(seed, step, chain);
  boost::random::normal_distribution<double> gauss;
  Eigen::VectorXd z(proposal.mean.size());
  for (Eigen::Index k = 0; k < z.size(); ++k) z[k] = gauss(engine);
  const double nu = proposal.degrees_of_freedom;
  const double chi2 = boost::random::chi_squared_distribution<double>(nu)(engine);
  boost::random::uniform_01<double> uniform;
  const double log_u = std::log(uniform(engine));
  return {proposal.mean + std::sqrt(nu / chi2) * (lower * z), log_u};
}

}  // namespace

double student_t_log_density(const StudentTProposal& proposal, const Eigen::VectorXd& x) {
  const Eigen::LLT<Eigen::MatrixXd> llt = checked_factor(proposal);
  if (x.size() != proposal.mean.size())
    throw std::invalid_argument("Student-t density: a point of " + std::to_string(x.size()) + " coordinates for " +
                                std::to_string(proposal.mean.size()));
  const double p = static_cast<double>(x.size()), nu = proposal.degrees_of_freedom;
  const Eigen::VectorXd whitened = llt.matrixL().solve(x - proposal.mean);
  const double log_det = 2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  return boost::math::lgamma(0.5 * (nu + p)) - boost::math::lgamma(0.5 * nu) -
         0.5 * p * std::log(nu * std::numbers::pi) - 0.5 * log_det -
         0.5 * (nu + p) * std::log1p(whitened.squaredNorm() / nu);
}

DesignMatrix draw_student_t(const StudentTProposal& proposal, int count, std::uint64_t seed, long step) {
  const Eigen::MatrixXd lower = checked_factor(proposal).matrixL();
  DesignMatrix draws(count, proposal.mean.size());
  for (int c = 0; c < count; ++c) draws.row(c) = draw_one(proposal, lower, seed, step, c).point.transpose();
  return draws;
}

EnsembleState initial_independence_state(const StudentTProposal& proposal, const BatchLogDensity& log_density,
                                         const IndependenceOptions& options) {
  if (options.chains < 1) throw std::invalid_argument("independence sampler: at least one chain");
  const Eigen::MatrixXd lower = checked_factor(proposal).matrixL();
  EnsembleState state;
  state.positions.resize(options.chains, proposal.mean.size());
  state.log_density = Eigen::VectorXd::Constant(options.chains, kNegativeInfinity);
  for (int round = 0; round < kInitialRounds && !state.log_density.allFinite(); ++round) {
    std::vector<Eigen::Index> pending;
    for (Eigen::Index c = 0; c < options.chains; ++c)
      if (!std::isfinite(state.log_density[c])) pending.push_back(c);
    DesignMatrix points(static_cast<Eigen::Index>(pending.size()), proposal.mean.size());
    for (std::size_t i = 0; i < pending.size(); ++i)  // rounds are negative steps: never a sampling step's draws
      points.row(static_cast<Eigen::Index>(i)) =
          draw_one(proposal, lower, options.seed, -1 - round, pending[i]).point.transpose();
    const Eigen::VectorXd values = evaluate_batch(log_density, points);
    for (std::size_t i = 0; i < pending.size(); ++i) {
      state.positions.row(pending[i]) = points.row(static_cast<Eigen::Index>(i));
      state.log_density[pending[i]] = values[static_cast<Eigen::Index>(i)];
    }
  }
  for (Eigen::Index c = 0; c < options.chains; ++c)
    if (!std::isfinite(state.log_density[c]))
      throw std::invalid_argument("independence sampler: chain " + std::to_string(c) + " found no point of finite " +
                                  "density in " + std::to_string(kInitialRounds) + " draws from the proposal");
  state.step = 0;
  return state;
}

EnsembleState independence_step(const EnsembleState& state, const StudentTProposal& proposal,
                                const BatchLogDensity& log_density, const IndependenceOptions& options,
                                std::vector<bool>* accepted) {
  const Eigen::Index chains = state.positions.rows();
  if (chains != options.chains || state.log_density.size() != chains || state.positions.cols() != proposal.mean.size())
    throw std::invalid_argument("independence sampler: the state has " + std::to_string(chains) + " chains of " +
                                std::to_string(state.positions.cols()) + " parameters; the options say " +
                                std::to_string(options.chains) + " of " + std::to_string(proposal.mean.size()));
  const Eigen::MatrixXd lower = checked_factor(proposal).matrixL();
  DesignMatrix proposals(chains, state.positions.cols());
  Eigen::VectorXd log_u(chains);
  for (Eigen::Index c = 0; c < chains; ++c) {
    ChainDraw draw = draw_one(proposal, lower, options.seed, state.step, c);
    proposals.row(c) = draw.point.transpose();
    log_u[c] = draw.log_uniform;
  }
  const Eigen::VectorXd proposal_density = evaluate_batch(log_density, proposals);
  EnsembleState next = state;
  next.step = state.step + 1;
  if (accepted != nullptr) accepted->assign(static_cast<std::size_t>(chains), false);
  for (Eigen::Index c = 0; c < chains; ++c) {
    if (!std::isfinite(proposal_density[c])) continue;
    const double log_weight_new = proposal_density[c] - student_t_log_density(proposal, proposals.row(c).transpose());
    const double log_weight_old =
        state.log_density[c] - student_t_log_density(proposal, state.positions.row(c).transpose());
    if (log_u[c] < log_weight_new - log_weight_old) {
      next.positions.row(c) = proposals.row(c);
      next.log_density[c] = proposal_density[c];
      if (accepted != nullptr) (*accepted)[static_cast<std::size_t>(c)] = true;
    }
  }
  return next;
}

}  // namespace rover::study
