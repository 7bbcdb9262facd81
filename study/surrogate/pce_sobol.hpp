// Sobol' indices of a polynomial chaos expansion in closed form (Sudret 2008):
// with orthonormal terms, E[Y] = c_0 and V = sum_{alpha != 0} c_alpha^2, and
// each partial variance is the sum of c_alpha^2 over the terms whose support
// (the inputs with alpha_i > 0) is the right set:
//   S1_i        support = {i}
//   ST_i        i in support
//   S2_ij       support = {i, j}                  (the pure interaction)
//   S2closed_ij support nonempty and within {i, j} (= S1_i + S1_j + S2_ij)
//
// Confidence intervals by the bootstrap over the training runs (Efron &
// Tibshirani 1993): the runs are resampled with replacement, the coefficients
// refitted by least squares on the selected terms, and the percentile
// interval of each index taken. Resamples that cannot resolve the terms
// (too many repeated runs) are skipped and counted.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"
#include "study/surrogate/polynomial_chaos.hpp"

namespace rover::study {

struct PceSobolIndices {
  bool defined = false;           // false: the output variance is zero
  std::string undefined_reason;   // why, when not defined
  double mean = 0.0, variance = 0.0;
  Eigen::VectorXd S1, ST;         // d each (empty when not defined)
  Eigen::MatrixXd S2, S2_closed;  // d x d, entries i < j filled, 0 elsewhere
};

// From the coefficients alone. Never NaN: a zero variance gives defined false.
PceSobolIndices pce_sobol_indices(const PolynomialChaosExpansion& expansion);
// The same from a coefficient vector on the expansion's terms.
PceSobolIndices pce_sobol_indices(const std::vector<MultiIndex>& multi_indices,
                                  const Eigen::VectorXd& coefficients);

// The indices the selected terms fix whatever their coefficients: S1_i is 0
// when no term has support {i} and 1 when every nonconstant term has; ST_i
// is 0 when no term holds input i and 1 when every nonconstant term does.
// Refitting the coefficients cannot move them, so their bootstrap intervals
// have zero width and show nothing of how uncertain the selection is.
struct PceIndicesFixedBySelection {
  std::vector<bool> S1, ST;  // d each
  bool any() const;
};
PceIndicesFixedBySelection pce_indices_fixed_by_selection(const std::vector<MultiIndex>& multi_indices,
                                                          int input_count);

struct PceBootstrapSettings {
  int resamples = 200;      // 2 .. 1,000,000
  double confidence = 0.95; // (0, 1)
  std::uint64_t seed = 1;   // the resamples depend only on (seed, resample, draw)
  // Read at every resample when set: once true, WorkStopped is thrown
  // (study/estimators/work_stopped.hpp; a signal ends a long bootstrap at once).
  const std::atomic<bool>* stop = nullptr;
};

struct PceSobolIntervals {
  int resamples_used = 0, resamples_skipped = 0;
  double confidence = 0.0;
  double mean_lower = 0, mean_upper = 0, variance_lower = 0, variance_upper = 0;
  Eigen::VectorXd S1_lower, S1_upper, ST_lower, ST_upper;
  Eigen::MatrixXd S2_lower, S2_upper;  // entries i < j filled, 0 elsewhere
  PceIndicesFixedBySelection fixed_by_selection;  // of the expansion's terms
};

// Percentile intervals by the bootstrap over the runs (x, y) the expansion was
// fitted on. Throws std::invalid_argument for bad settings or sizes, or if the
// expansion's indices are undefined; std::runtime_error if no resample could
// be refitted.
PceSobolIntervals bootstrap_pce_sobol(const PolynomialChaosExpansion& expansion,
                                      const DesignMatrix& x, const Eigen::VectorXd& y,
                                      const PceBootstrapSettings& settings);

}  // namespace rover::study
