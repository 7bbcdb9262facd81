// Convergence diagnostics of an ensemble MCMC run.
//
// Integrated autocorrelation time (Sokal 1997; as recommended for ensemble
// samplers by Goodman & Weare 2010 and Foreman-Mackey et al. 2013): the
// normalised autocorrelation function rho(t) of each walker's chain (by FFT,
// zero-padded, each walker about its own mean, biased 1/N normalisation) is
// averaged over the walkers, and tau(M) = 1 + 2 sum_{t=1..M} rho(t) is taken
// at the smallest window M with M >= c tau(M) (c = 5). If no window up to N-1
// satisfies this, tau(N-1) is returned: the chain is far too short to trust it.
// Like any truncated-window estimate it is biased low on short chains, and on
// a negatively autocorrelated chain (rare for the stretch move) the window
// closes at once and tau can come out near 0.
//
// Split R-hat (Gelman et al. 2013, BDA3 section 11.4): each walker's chain is
// cut into two halves (the middle draw of an odd length is dropped) and the
// between- and within-chain variances of the 2 x walkers half-chains give
// R-hat = sqrt(((n-1)/n W + B/n) / W).
//
// Nested R-hat (Margossian, Hoffman, Sountsov, Riou-Durand, Vehtari and
// Vehtari 2022, "Nested R-hat: assessing the convergence of Markov chain
// Monte Carlo when running many short chains"), split like R-hat: every
// walker's chain is cut in halves, and the first halves and the second halves
// are each cut into `superchains` groups of consecutive walkers, so a drift
// between the halves shows as well as a disagreement between walkers;
// R = sqrt(1 + B / W), B the variance of
// the superchain means, W the mean over superchains of the variance of their
// walkers' means plus the mean within-walker variance. Each walker of an
// ensemble holds few independent draws, so the split R-hat of single walkers
// stays near 1 + 1 / (draws per walker) however long the ensemble runs; the
// superchains' means average those out, and R -> 1 as the chain mixes.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace rover::study {

// chain: steps x walkers samples of ONE parameter (at least 4 steps).
// NaN when no walker moves at all (zero variance in every walker).
double integrated_autocorrelation_time(const Eigen::MatrixXd& chain, double window_c = 5.0);
double effective_sample_size(const Eigen::MatrixXd& chain);  // steps * walkers / tau
// NaN when every half-chain is constant.
double split_rhat(const Eigen::MatrixXd& chain);
// superchains >= 2 groups of chain.cols() / superchains consecutive walkers
// per half (the remainder left out); NaN when no walker moves.
double nested_rhat(const Eigen::MatrixXd& chain, int superchains);

// The nested R-hat below which chains count as mixed unless a study sets its
// own (Margossian et al. 2022 use 1.01 with many short chains).
constexpr double kDefaultMaxNestedRhat = 1.01;
// Above this the walkers disagree outright: not converged, or several modes.
constexpr double kDisagreeingNestedRhat = 1.1;

struct ChainDiagnostics {
  double acceptance_fraction = 0;
  Eigen::VectorXd autocorrelation_time, effective_sample_size, split_rhat;  // per parameter
  // Per parameter: nested R-hat over 4 superchains (the split R-hat with fewer than 8 walkers).
  Eigen::VectorXd nested_rhat;
  bool chain_too_short = false;  // steps < 50 * max autocorrelation time, or a parameter never moves
  std::string warning;           // human text when too short or R-hat >= max_rhat / > 1.1; empty if fine
};

// samples: for each parameter a steps x walkers matrix (all the same shape);
// accepted_moves: accepted proposals over ALL the steps in `samples`, so the
// acceptance fraction is accepted_moves / (steps * walkers) before discarding.
// The first `discard_steps` steps (burn-in) are left out of everything else.
// `names` (one per parameter, or empty: "parameter q") label the warning; a
// nested R-hat of `max_rhat` or more is warned about.
ChainDiagnostics diagnose_chain(const std::vector<Eigen::MatrixXd>& samples, long accepted_moves,
                                int discard_steps = 0, const std::vector<std::string>& names = {},
                                double max_rhat = kDefaultMaxNestedRhat);

}  // namespace rover::study
