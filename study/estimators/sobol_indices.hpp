// Variance-based global sensitivity indices (Sobol' 1993) from a pick-freeze
// design (Saltelli 2002; Saltelli et al. 2010), with bootstrap confidence
// intervals over the design's groups (Efron & Tibshirani 1993; BCa: Efron 1987).
//
// Estimators (f0 and V: mean and variance of the A and B runs):
//   kSaltelliJansen  S1_i = (1/N) sum f(B) (f(A_B^i) - f(A)) / V      (Saltelli et al. 2010)
//                    ST_i = (1/2N) sum (f(A) - f(A_B^i))^2 / V         (Jansen 1999)
//                    S2_ij = (1/N) sum (f(B_A^i) f(A_B^j) - f(A) f(B)) / V - S1_i - S1_j
//                                                                      (Saltelli 2002)
//   kMartinez        S1_i = corr(f(B), f(A_B^i)),  ST_i = 1 - corr(f(A), f(A_B^i)),
//                    S2_ij = corr(f(B_A^i), f(A_B^j)) - S1_i - S1_j    (Martinez 2011)
// The outputs are centred on f0 before the products are formed, which removes
// the O(f0^2 / V) noise of the uncentred product forms (Sobol' 2001).
//
// Failed runs: a non-finite output drops its whole group (the A, B and mixed
// runs share their rows of A and B, so a group is the unit of the estimator);
// nothing is imputed. The bootstrap resamples the groups that remain.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "study/estimators/bootstrap_resolution.hpp"
#include "study/estimators/design_matrix.hpp"

namespace rover::study {

// Pick-freeze layout (Saltelli 2002/2010): N groups; group g holds, in this order,
//   k = 0: A_g,   k = 1: B_g,   k = 2 .. d+1: A_B^(i) (row g of A with column i taken from B),
//   k = d+2 .. 2d+1 (second_order only): B_A^(i) (row g of B with column i taken from A).
// Run index r = g * runs_per_group() + k.
struct PickFreezeLayout {
  int base_samples = 0;  // N
  int dimensions = 0;    // d
  bool second_order = false;
  int runs_per_group() const;  // d + 2, or 2d + 2
  int total_runs() const;      // N * runs_per_group()
};

// A, B: N x d (unit or physical; only columns are swapped). Returns total_runs() x d.
// Throws std::invalid_argument if A and B differ in shape or are empty.
DesignMatrix pick_freeze_design(const DesignMatrix& A, const DesignMatrix& B, bool second_order);

enum class SobolEstimator { kSaltelliJansen, kMartinez };

// kPercentile: the percentile interval of the bootstrap replicates. kBca: the
// bias-corrected and accelerated interval (Efron 1987), its acceleration from
// the leave-one-group-out jackknife; second-order accurate in theory, but on the
// test models (linear, g-function; N = 64 .. 512) its coverage equals the
// percentile interval's within the Monte Carlo noise of 200-300 repeats, so the
// simpler one is the default. An index whose bootstrap replicates are all equal
// up to rounding (an input that does not enter the model, under Jansen's ST)
// gets the degenerate interval spanning the point and the replicates.
enum class BootstrapInterval { kPercentile, kBca };

struct SobolOptions {
  SobolEstimator estimator = SobolEstimator::kSaltelliJansen;
  int bootstrap_resamples = 1000;  // 0: no intervals (NaN bounds)
  double confidence = 0.95;
  std::uint64_t seed = 1;  // bootstrap resampling is deterministic
  BootstrapInterval interval = BootstrapInterval::kPercentile;
  // Read at every resample when set: once true, WorkStopped is thrown
  // (work_stopped.hpp; a signal ends a long bootstrap at once).
  const std::atomic<bool>* stop = nullptr;
};

struct SobolIndices {
  Eigen::VectorXd S1, ST, S1_lower, S1_upper, ST_lower, ST_upper;  // d each
  Eigen::MatrixXd S2, S2_lower, S2_upper;  // d x d, entries i < j filled, NaN elsewhere; empty if
                                           // the layout has no second order
  double mean = 0, variance = 0;           // of the output, from the A and B runs used
  int groups_total = 0, groups_used = 0;
  std::vector<int> dropped_groups;  // groups with a failed (non-finite) run, dropped whole
  bool has_intervals = false;       // false: no bootstrap asked for, or too few groups to resample
};

// The fewest complete groups (no failed run) the estimators need.
inline constexpr int kMinCompleteSobolGroups = 2;
// The fewest complete groups the bootstrap resamples (kMinBootstrapUnits):
// below it the bounds are NaN and has_intervals is false.
inline constexpr int kMinBootstrapSobolGroups = kMinBootstrapUnits;

// y: one output per run, in layout order; a non-finite value marks a failed run and its whole group
// is dropped (never silently imputed). `variance` is the unbiased sample variance of the 2 N' A and
// B outputs of the N' groups used. Throws std::invalid_argument if y does not match the layout, if
// fewer than 2 groups remain or if the output variance is zero (at rounding level).
SobolIndices estimate_sobol_indices(const PickFreezeLayout& layout, const Eigen::VectorXd& y,
                                    const SobolOptions& options);

// Point estimates for many outputs at once (a curve y(t)): Y is total_runs() x T; rows with any
// non-finite value drop their group. S1, ST: d x T; variance: T; aggregated_S1/ST: d, the
// variance-weighted averages sum_t V(t) S_i(t) / sum_t V(t) (generalised indices of Gamboa et al.
// 2013); time samples with zero variance give NaN indices and weight 0 (all zero: NaN aggregates).
struct SobolIndicesAlongTime {
  Eigen::MatrixXd S1, ST;
  Eigen::VectorXd variance, aggregated_S1, aggregated_ST;
  int groups_used = 0;
};
// The times at which the indices are undefined (NaN: no variance there).
long long undefined_time_count(const SobolIndicesAlongTime& indices);
SobolIndicesAlongTime estimate_sobol_indices_along_time(const PickFreezeLayout& layout,
                                                        const Eigen::MatrixXd& Y,
                                                        SobolEstimator estimator);

}  // namespace rover::study
