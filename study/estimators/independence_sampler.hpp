// Independence Metropolis-Hastings (Tierney 1994, section 2.3.3) with a
// multivariate Student-t proposal: the sampler for a posterior that a
// converged least-squares fit already describes well (its Laplace
// approximation), as after a calibration fit.
//
// C chains run side by side. At each step every chain c draws a proposal Y_c
// from q = t_nu(mean, scale), independently of its state X_c, and accepts it
// with probability min(1, w(Y_c) / w(X_c)), w = pi / q. The C proposals are
// evaluated in ONE batch call, so the caller can fan them out over MPI ranks.
// When q is close to pi almost every proposal is accepted and successive
// states are nearly independent: the autocorrelation time is near 1, against
// tens of steps for a random-walk or stretch move. When q misses a part of
// pi (a second mode, a much heavier tail) the chains stick there, and the
// effective sample size and R-hat of study/estimators/mcmc_diagnostics.hpp
// say so.
//
// The heavy tails of t_nu (nu = 4 by default) keep w bounded where pi is at
// most about Gaussian, which makes the chain uniformly ergodic (Mengersen &
// Tweedie 1996).
//
// Reproducibility: the proposal and the acceptance draw of chain c at step s
// come from an engine seeded by a SplitMix64 hash of (seed, s, c) only, so
// the chains are bit-identical however the batch is distributed, and a run
// resumed from a saved state continues exactly as an uninterrupted one.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"
#include "study/estimators/ensemble_sampler.hpp"

namespace rover::study {

// The multivariate Student-t distribution t_nu(mean, scale): scale is
// symmetric positive definite; the covariance is scale nu / (nu - 2).
struct StudentTProposal {
  Eigen::VectorXd mean;
  Eigen::MatrixXd scale;
  double degrees_of_freedom = 4.0;
};

// Its log density at x (normalised). Throws std::invalid_argument when the
// scale is not positive definite or the dimensions disagree.
double student_t_log_density(const StudentTProposal& proposal, const Eigen::VectorXd& x);

// `count` draws (rows) from the proposal with the engine of (seed, step, row).
DesignMatrix draw_student_t(const StudentTProposal& proposal, int count, std::uint64_t seed, long step);

struct IndependenceOptions {
  int chains = 16;  // >= 2 for R-hat
  std::uint64_t seed = 1;
};

// The state holds one position per chain (EnsembleState's rows are chains).
// The initial state: `count` draws from the proposal at step 0, evaluated in
// one batch; draws outside the support are drawn again (at most 100 rounds).
// Throws std::invalid_argument when a chain finds no point of finite density.
EnsembleState initial_independence_state(const StudentTProposal& proposal, const BatchLogDensity& log_density,
                                         const IndependenceOptions& options);

// One step of every chain: the state after step state.step. accepted
// (optional): resized to the chains; whether each proposal was accepted.
EnsembleState independence_step(const EnsembleState& state, const StudentTProposal& proposal,
                                const BatchLogDensity& log_density, const IndependenceOptions& options,
                                std::vector<bool>* accepted = nullptr);

}  // namespace rover::study
