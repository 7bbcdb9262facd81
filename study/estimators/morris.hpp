// Elementary-effects screening (Morris 1991) with the absolute-mean measure
// mu* of Campolongo, Cariboni & Saltelli (2007) and a bootstrap percentile
// interval for mu* over trajectories (Efron & Tibshirani 1993).
//
// A trajectory starts at a random point of the p-level grid {0, 1/(p-1), ...,
// 1} in the unit cube and moves each input once, in random order, by the jump
// Delta = p / (2 (p - 1)) (p/2 levels; Morris 1991, Saltelli et al. 2004):
// an input in the lower half of the grid moves up, one in the upper half down,
// so every point stays on the grid and the direction of each jump is random
// (Morris's random orientation of the trajectory). No two trajectories take
// the same step of an input (the same pair of points), so every elementary
// effect is a new one.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "study/estimators/bootstrap_resolution.hpp"
#include "study/estimators/design_matrix.hpp"

namespace rover::study {

// Morris (1991) one-at-a-time trajectories on a p-level grid in the unit cube: levels k / (p - 1)
// for k = 0..p-1, a jump of p/2 levels (p even), p / (2 (p - 1)) in unit coordinates. A jump of
// exactly half the cube would be blind to any effect periodic in half the range (sin^2 over
// [-pi, pi]). A distribution with infinite support is mapped from the centred levels
// (morris_centred_level). Trajectory t is rows t(d+1) .. t(d+1)+d.
struct MorrisDesign {
  DesignMatrix points;             // r (d + 1) x d, unit coordinates
  std::vector<int> changed_input;  // r d entries: which input changes between consecutive rows
  std::vector<double> step;        // r d entries: signed jump in unit coordinates
  int trajectories = 0, dimensions = 0, levels = 0;
};
// How many distinct elementary-effect steps each input has: a step of input i
// is the pair of grid points (x, x + Delta e_i), named by the levels of the
// other inputs and the lower level of i, so levels^(d-1) x levels/2 of them
// (capped at kManySteps). Every trajectory takes one step of each input, so
// this is also the most trajectories whose steps never repeat.
inline constexpr double kManySteps = 1e15;
double distinct_morris_steps(int dimensions, int levels);
// No two trajectories share a step of any input (two that did would give
// that input the same elementary effect twice, counted as independent in
// sigma and the bootstrap; a repeated or reversed trajectory repeats all its
// steps). Trajectories are drawn at random and redrawn while a step repeats;
// when random draws keep colliding (near the bound), the whole design is drawn
// instead from a packing in which no step can repeat (morris.cpp). The design
// is a function of the seed. Throws std::invalid_argument unless dimensions >= 1,
// trajectories >= 1 and levels is even, >= 2, and for more trajectories than
// distinct_morris_steps.
MorrisDesign morris_design(int dimensions, int trajectories, int levels, std::uint64_t seed);

// The unit coordinate u = k / (p - 1) of a level moved to the centre of its
// cell, (k + 1/2) / p: where a distribution with infinite support is read
// (its quantiles at 0 and 1 are infinite).
inline double morris_centred_level(double u, int levels) { return (0.5 + u * (levels - 1)) / levels; }

struct MorrisOptions {
  int bootstrap_resamples = 1000;  // 0: no interval (NaN bounds)
  double confidence = 0.95;
  std::uint64_t seed = 1;
  // Read at every resample when set: once true, WorkStopped is thrown
  // (work_stopped.hpp; a signal ends a long bootstrap at once).
  const std::atomic<bool>* stop = nullptr;
};
struct MorrisResult {
  Eigen::VectorXd mu, mu_star, sigma, mu_star_lower, mu_star_upper;  // d each; EE in unit coords
  std::vector<int> ranking;  // inputs by mu_star, largest first (ties: lower index first)
  int trajectories_used = 0;
  std::vector<int> dropped_trajectories;  // with a non-finite output, dropped whole
  bool has_intervals = false;  // false: no bootstrap asked for, or too few trajectories to resample
};
// The fewest complete trajectories (no failed run) morris_effects needs.
inline constexpr int kMinMorrisTrajectories = 1;
// The fewest complete trajectories the bootstrap resamples (kMinBootstrapUnits):
// below it the mu* bounds are NaN and has_intervals is false.
inline constexpr int kMinBootstrapMorrisTrajectories = kMinBootstrapUnits;

// y: one output per row of design.points. Elementary effect of input i on trajectory t:
// EE = (y(after) - y(before)) / step. mu and mu_star are means over the trajectories used, sigma
// their sample standard deviation (n - 1; NaN with one trajectory). Throws std::invalid_argument if
// y does not match the design or no trajectory is complete.
MorrisResult morris_effects(const MorrisDesign& design, const Eigen::VectorXd& y,
                            const MorrisOptions& options);

}  // namespace rover::study
