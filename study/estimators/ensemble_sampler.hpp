// Affine-invariant ensemble MCMC: the stretch move of Goodman & Weare (2010),
// in the parallel form of Foreman-Mackey et al. (2013, section 3).
//
// The ensemble of W walkers (W even) is split into two halves, S0 = walkers
// 0 .. W/2-1 and S1 = W/2 .. W-1. A step first moves every walker k of S0
// against the current positions of S1, then every walker of S1 against the
// updated S0: walker k picks a partner j uniformly from the other half, draws
// z from g(z) ~ 1/sqrt(z) on [1/a, a] and proposes Y = X_j + z (X_k - X_j),
// accepted with probability min(1, z^(p-1) pi(Y) / pi(X_k)). The proposals of
// one half are evaluated in ONE batch call, so the caller can fan them out
// over MPI ranks.
//
// Reproducibility: the three random numbers of walker k at step s (partner,
// z, acceptance) come from a Boost.Random engine seeded by a SplitMix64 hash
// of (seed, s, k) and nothing else. The chain is therefore bit-identical
// however the batch callback distributes or orders its rows, and a run resumed
// from a saved EnsembleState continues exactly as an uninterrupted one: the
// state holds everything (there is no engine state to save).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"

namespace rover::study {

// Log density of a batch of points (rows), evaluated together so the caller
// can fan the batch out over MPI ranks; returns one value per row. -inf (or
// NaN, treated as -inf) = outside the support / failed model run. +inf is an
// error (the density is not normalisable there).
using BatchLogDensity = std::function<Eigen::VectorXd(const DesignMatrix& points)>;

// Calls the batch density and maps NaN to -inf; throws std::runtime_error on a
// wrong number of values or +inf.
Eigen::VectorXd evaluate_batch(const BatchLogDensity& log_density, const DesignMatrix& points);

struct EnsembleOptions {
  int walkers = 32;            // even, >= 2 * parameters
  double stretch_scale = 2.0;  // a > 1; Goodman & Weare's default is 2
  std::uint64_t seed = 1;
};

struct EnsembleState {
  DesignMatrix positions;       // walkers x p
  Eigen::VectorXd log_density;  // walkers
  long step = 0;                // steps completed
};

// One full step (both halves): the state after step `state.step`.
// accepted (optional): resized to the walkers; whether each walker's proposal
// was accepted. Throws std::invalid_argument if the options do not fit the
// state (odd walkers, walkers < 2p, a <= 1) and std::runtime_error if the
// callback returns the wrong number of values or +inf.
EnsembleState ensemble_step(const EnsembleState& state, const BatchLogDensity& log_density,
                            const EnsembleOptions& options, std::vector<bool>* accepted = nullptr);

// The initial state (step 0): evaluates `initial_positions` (walkers x p) in
// one batch; throws std::invalid_argument naming the first walker whose log
// density is not finite.
EnsembleState initial_ensemble_state(const DesignMatrix& initial_positions,
                                     const BatchLogDensity& log_density);

// A recorded run, in the layout diagnose_chain (study/estimators/mcmc_diagnostics.hpp)
// takes.
struct EnsembleChain {
  std::vector<Eigen::MatrixXd> samples;  // per parameter: steps x walkers
  Eigen::MatrixXd log_density;           // steps x walkers
  long accepted_moves = 0;               // over all steps and walkers
  EnsembleState final_state;
};

// `steps` calls of ensemble_step from `start`; row i of the samples is the
// state after step start.step + i + 1.
EnsembleChain run_ensemble(const EnsembleState& start, const BatchLogDensity& log_density,
                           const EnsembleOptions& options, long steps);

}  // namespace rover::study
