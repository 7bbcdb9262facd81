#include "study/estimators/mcmc_diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>
#include <stdexcept>

// Eigen's FFT module (unsupported/) converts an index to double inside inv();
// the warning is Eigen's, not this file's.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#include <unsupported/Eigen/FFT>
#pragma GCC diagnostic pop

namespace rover::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void check_chain(const Eigen::MatrixXd& chain, const char* what) {
  if (chain.rows() < 4 || chain.cols() < 1)
    throw std::invalid_argument(std::string(what) + ": a chain needs at least 4 steps and 1 walker (got " +
                                std::to_string(chain.rows()) + " x " + std::to_string(chain.cols()) + ")");
  if (!chain.allFinite()) throw std::invalid_argument(std::string(what) + ": non-finite sample");
}

// Normalised autocorrelation rho(0..N-1) of each walker, averaged over the
// walkers that move; empty if none does.
std::vector<double> mean_autocorrelation(const Eigen::MatrixXd& chain) {
  const auto n = static_cast<std::size_t>(chain.rows());
  std::size_t padded = 1;
  while (padded < 2 * n) padded *= 2;  // no circular wrap-around up to lag n-1
  Eigen::FFT<double> fft;
  std::vector<double> x(padded), acov;
  std::vector<std::complex<double>> spectrum;
  std::vector<double> mean_rho(n, 0.0);
  int moving_walkers = 0;
  for (Eigen::Index w = 0; w < chain.cols(); ++w) {
    const double mean = chain.col(w).mean();
    std::fill(x.begin(), x.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i) x[i] = chain(static_cast<Eigen::Index>(i), w) - mean;
    fft.fwd(spectrum, x);
    for (auto& c : spectrum) c = std::norm(c);
    fft.inv(acov, spectrum);
    if (!(acov[0] > 0.0)) continue;  // a walker that never moved carries no information
    ++moving_walkers;
    for (std::size_t t = 0; t < n; ++t) mean_rho[t] += acov[t] / acov[0];
  }
  if (moving_walkers == 0) return {};
  for (double& r : mean_rho) r /= moving_walkers;
  return mean_rho;
}

}  // namespace

double integrated_autocorrelation_time(const Eigen::MatrixXd& chain, double window_c) {
  check_chain(chain, "integrated_autocorrelation_time");
  if (!(window_c > 0.0)) throw std::invalid_argument("integrated_autocorrelation_time: window_c must be > 0");
  const std::vector<double> rho = mean_autocorrelation(chain);
  if (rho.empty()) return kNaN;
  double tau = 1.0;  // tau(0)
  for (std::size_t m = 1; m < rho.size(); ++m) {
    tau += 2.0 * rho[m];
    if (static_cast<double>(m) >= window_c * tau) break;
  }
  return tau;
}

double effective_sample_size(const Eigen::MatrixXd& chain) {
  return static_cast<double>(chain.size()) / integrated_autocorrelation_time(chain);
}

constexpr int kSuperchains = 4;

double split_rhat(const Eigen::MatrixXd& chain) {
  check_chain(chain, "split_rhat");
  const Eigen::Index n = chain.rows() / 2;  // length of each half-chain
  const Eigen::Index m = 2 * chain.cols();  // number of half-chains
  Eigen::VectorXd means(m), variances(m);
  for (Eigen::Index w = 0; w < chain.cols(); ++w)
    for (Eigen::Index h = 0; h < 2; ++h) {
      const auto half = chain.col(w).segment(h == 0 ? 0 : chain.rows() - n, n);
      const double mean = half.mean();
      means[2 * w + h] = mean;
      variances[2 * w + h] = (half.array() - mean).square().sum() / static_cast<double>(n - 1);
    }
  const double nd = static_cast<double>(n);
  const double within = variances.mean();
  const double between = nd * (means.array() - means.mean()).square().sum() / static_cast<double>(m - 1);
  if (!(within > 0.0)) return kNaN;
  const double pooled = (nd - 1.0) / nd * within + between / nd;
  return std::sqrt(pooled / within);
}

double nested_rhat(const Eigen::MatrixXd& full_chain, int superchains) {
  check_chain(full_chain, "nested_rhat");
  if (superchains < 2 || full_chain.cols() < superchains)
    throw std::invalid_argument("nested_rhat: need at least 2 superchains of at least one walker each, got " +
                                std::to_string(superchains) + " superchains of " +
                                std::to_string(full_chain.cols()) + " walkers");
  // Split: the first halves of the walkers, then their second halves.
  const Eigen::Index half = full_chain.rows() / 2;
  Eigen::MatrixXd chain(half, 2 * full_chain.cols());
  chain << full_chain.topRows(half), full_chain.bottomRows(half);
  superchains *= 2;
  const Eigen::Index walkers_per_group = chain.cols() / superchains;
  const double n = static_cast<double>(chain.rows());
  Eigen::VectorXd group_means(superchains);
  double within = 0.0;  // mean over superchains of (between walkers + within walkers)
  for (int k = 0; k < superchains; ++k) {
    const auto group = chain.middleCols(k * walkers_per_group, walkers_per_group);
    const Eigen::RowVectorXd walker_means = group.colwise().mean();
    group_means[k] = walker_means.mean();
    const double between_walkers =
        walkers_per_group > 1
            ? (walker_means.array() - group_means[k]).square().sum() / static_cast<double>(walkers_per_group - 1)
            : 0.0;
    const double within_walkers =
        (group.rowwise() - walker_means).array().square().sum() / ((n - 1.0) * static_cast<double>(walkers_per_group));
    within += (between_walkers + within_walkers) / superchains;
  }
  const double between = (group_means.array() - group_means.mean()).square().sum() / (superchains - 1.0);
  if (!(within > 0.0)) return kNaN;
  return std::sqrt(1.0 + between / within);
}

ChainDiagnostics diagnose_chain(const std::vector<Eigen::MatrixXd>& samples, long accepted_moves,
                                int discard_steps, const std::vector<std::string>& names, double max_rhat) {
  const auto label = [&](Eigen::Index q) {
    return static_cast<std::size_t>(q) < names.size() ? names[static_cast<std::size_t>(q)]
                                                      : "parameter " + std::to_string(q);
  };
  if (samples.empty()) throw std::invalid_argument("diagnose_chain: no parameters");
  const Eigen::Index steps = samples.front().rows(), walkers = samples.front().cols();
  for (const auto& s : samples)
    if (s.rows() != steps || s.cols() != walkers)
      throw std::invalid_argument("diagnose_chain: parameters have chains of different shapes");
  if (discard_steps < 0 || steps - discard_steps < 4)
    throw std::invalid_argument("diagnose_chain: " + std::to_string(discard_steps) +
                                " discarded steps leave fewer than 4 of " + std::to_string(steps));
  if (accepted_moves < 0 || accepted_moves > steps * walkers)
    throw std::invalid_argument("diagnose_chain: accepted_moves must be in [0, steps * walkers]");

  ChainDiagnostics d;
  d.acceptance_fraction = static_cast<double>(accepted_moves) / static_cast<double>(steps * walkers);
  const auto p = static_cast<Eigen::Index>(samples.size());
  const Eigen::Index kept = steps - discard_steps;
  d.autocorrelation_time.resize(p);
  d.effective_sample_size.resize(p);
  d.split_rhat.resize(p);
  d.nested_rhat.resize(p);
  std::ostringstream warning;
  double max_tau = 0.0;
  for (Eigen::Index q = 0; q < p; ++q) {
    const Eigen::MatrixXd chain = samples[static_cast<std::size_t>(q)].bottomRows(kept);
    const double tau = integrated_autocorrelation_time(chain);
    d.autocorrelation_time[q] = tau;
    d.effective_sample_size[q] = static_cast<double>(chain.size()) / tau;
    d.split_rhat[q] = split_rhat(chain);
    d.nested_rhat[q] = walkers >= 2 * kSuperchains ? nested_rhat(chain, kSuperchains) : d.split_rhat[q];
    if (std::isnan(tau)) {
      warning << label(q) << " never moves; ";
      d.chain_too_short = true;
    } else {
      max_tau = std::max(max_tau, tau);
    }
    if (d.nested_rhat[q] > kDisagreeingNestedRhat)
      warning << label(q) << ": nested R-hat " << d.nested_rhat[q] << " > " << kDisagreeingNestedRhat
              << ", the walkers disagree (not converged or several modes); ";
    else if (d.nested_rhat[q] >= max_rhat)
      warning << label(q) << ": nested R-hat " << d.nested_rhat[q] << " >= max_rhat " << max_rhat << "; ";
  }
  if (static_cast<double>(kept) < 50.0 * max_tau) {
    d.chain_too_short = true;
    warning << "chain too short: " << kept << " steps < 50 x autocorrelation time " << max_tau
            << " (intervals and the autocorrelation time itself are unreliable); ";
  }
  d.warning = warning.str();
  if (!d.warning.empty()) d.warning.resize(d.warning.size() - 2);  // the last "; "
  return d;
}

}  // namespace rover::study
