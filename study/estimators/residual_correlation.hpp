// Whether a fit leaves structure in its residuals: their lag-1
// autocorrelation (the statistic behind Durbin & Watson 1950, d ~ 2(1 - r1)).
// Least-squares intervals assume independent noise; residuals of a model that
// follows the data are then uncorrelated, r1 ~ N(0, 1/n). A model that does
// not follow a curve (data of another scenario, a missing effect) leaves a
// smooth misfit, r1 near 1, and so does noise filtered by the acquisition.
// Either way the intervals are too narrow: for AR(1) errors the variance of a
// mean grows by (1 + r1) / (1 - r1) (Box, Jenkins & Reinsel, ch. 2).
//
// Pure functions of their arguments; they may run concurrently.
#pragma once

#include <limits>
#include <span>

namespace rover::study {

struct ResidualCorrelation {
  // Structure is flagged above both: a correlation that matters, and one
  // independent noise reaches with probability below 1e-4 (4 sd of r1).
  static constexpr double kLargeLag1 = 0.5;
  static constexpr double kWhiteNoiseSd = 4.0;

  std::size_t points = 0;
  double lag1 = std::numeric_limits<double>::quiet_NaN();  // NaN below 3 points or for constant residuals

  // kWhiteNoiseSd / sqrt(n): independent noise stays below it.
  double white_noise_bound() const;
  bool model_leaves_structure() const;
  // sqrt((1 + r1) / (1 - r1)): how much too narrow intervals that assume
  // independent noise are, for AR(1) errors (infinite at r1 = 1).
  double interval_narrowing() const;
};

// r1 = sum_i (e_i - m)(e_i+1 - m) / sum_i (e_i - m)^2 of residuals in the order
// of their times (m their mean).
ResidualCorrelation residual_correlation(std::span<const double> residuals);

}  // namespace rover::study
