// See residual_correlation.hpp.
#include "study/estimators/residual_correlation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace rover::study {
namespace {

// Deviations from the mean below this many rounding units of the largest
// residual are rounding.
constexpr double kRoundingUnits = 64.0;

}  // namespace

double ResidualCorrelation::white_noise_bound() const {
  return points == 0 ? std::numeric_limits<double>::infinity()
                     : kWhiteNoiseSd / std::sqrt(static_cast<double>(points));
}

bool ResidualCorrelation::model_leaves_structure() const {
  return lag1 > std::max(kLargeLag1, white_noise_bound());
}

double ResidualCorrelation::interval_narrowing() const {
  if (!(lag1 > 0.0)) return 1.0;
  return lag1 >= 1.0 ? std::numeric_limits<double>::infinity() : std::sqrt((1.0 + lag1) / (1.0 - lag1));
}

ResidualCorrelation residual_correlation(std::span<const double> residuals) {
  ResidualCorrelation c;
  c.points = residuals.size();
  if (c.points < 3) return c;
  const double mean = std::accumulate(residuals.begin(), residuals.end(), 0.0) / static_cast<double>(c.points);
  double sum_squares = 0.0, sum_lagged = 0.0;
  for (std::size_t i = 0; i < c.points; ++i) {
    const double e = residuals[i] - mean;
    sum_squares += e * e;
    if (i + 1 < c.points) sum_lagged += e * (residuals[i + 1] - mean);
  }
  // Residuals equal to rounding (a constant series) have no correlation.
  double largest = 0.0;
  for (double v : residuals) largest = std::max(largest, std::abs(v));
  const double rounding = kRoundingUnits * std::numeric_limits<double>::epsilon() * largest;
  if (sum_squares > static_cast<double>(c.points) * rounding * rounding) c.lag1 = sum_lagged / sum_squares;
  return c;
}

}  // namespace rover::study
