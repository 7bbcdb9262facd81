// Tests of study/estimators/residual_correlation: the lag-1 autocorrelation on
// series of known structure. Independent normal draws give r1 ~ N(-1/n, 1/n)
// (Anderson 1942) and are never flagged; an AR(1) series x_i = phi x_i-1 + e_i
// gives r1 -> phi, and the variance of its mean, measured over replicates,
// is (1 + phi) / (1 - phi) times that of independent draws, the square of
// interval_narrowing(); a smooth misfit gives r1 near 1.
#include "study/estimators/residual_correlation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace rover::study {
namespace {

std::vector<double> ar1_series(double phi, std::size_t n, std::mt19937_64& engine) {
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<double> x(n);
  double previous = noise(engine) / std::sqrt(1.0 - phi * phi);  // stationary start
  for (double& v : x) v = previous = phi * previous + noise(engine);
  return x;
}

double mean_of(const std::vector<double>& x) {
  double sum = 0.0;
  for (double v : x) sum += v;
  return sum / static_cast<double>(x.size());
}

TEST(ResidualCorrelation, IndependentNoiseIsNeverFlagged) {
  constexpr std::size_t kPoints = 200;
  constexpr int kReplicates = 2000;
  std::mt19937_64 engine(3);
  double sum = 0.0, sum_squares = 0.0;
  int flagged = 0;
  for (int k = 0; k < kReplicates; ++k) {
    const ResidualCorrelation c = residual_correlation(ar1_series(0.0, kPoints, engine));
    sum += c.lag1;
    sum_squares += c.lag1 * c.lag1;
    flagged += c.model_leaves_structure() ? 1 : 0;
  }
  const double mean = sum / kReplicates, sd = std::sqrt(sum_squares / kReplicates - mean * mean);
  const double n = static_cast<double>(kPoints);
  EXPECT_NEAR(mean, -1.0 / n, 3.0 / std::sqrt(n * kReplicates));
  EXPECT_NEAR(sd, 1.0 / std::sqrt(n), 0.1 / std::sqrt(n));
  EXPECT_EQ(flagged, 0);
}

TEST(ResidualCorrelation, AnAutoregressiveSeriesGivesItsCoefficient) {
  std::mt19937_64 engine(5);
  for (double phi : {0.3, 0.8, 0.95}) {
    const ResidualCorrelation c = residual_correlation(ar1_series(phi, 20000, engine));
    EXPECT_NEAR(c.lag1, phi, 0.02) << phi;
    EXPECT_EQ(c.model_leaves_structure(), phi > ResidualCorrelation::kLargeLag1) << phi;
  }
}

TEST(ResidualCorrelation, TheNarrowingIsThatOfTheMeanOfAnAutoregressiveSeries) {
  constexpr double kPhi = 0.8;
  constexpr std::size_t kPoints = 2000;
  constexpr int kReplicates = 800;
  std::mt19937_64 engine(7);
  double sum = 0.0, sum_squares = 0.0;
  for (int k = 0; k < kReplicates; ++k) {
    const double m = mean_of(ar1_series(kPhi, kPoints, engine));
    sum += m;
    sum_squares += m * m;
  }
  const double variance_of_mean = sum_squares / kReplicates - (sum / kReplicates) * (sum / kReplicates);
  const double independent_variance = 1.0 / (1.0 - kPhi * kPhi) / static_cast<double>(kPoints);
  ResidualCorrelation c;
  c.points = kPoints;
  c.lag1 = kPhi;
  // The replicates' variance has a relative sd of sqrt(2 / 800) = 5 %.
  EXPECT_NEAR(std::sqrt(variance_of_mean / independent_variance), c.interval_narrowing(), 0.06 * 3.0);
}

TEST(ResidualCorrelation, ASmoothMisfitIsFlagged) {
  // 150 points over one period of a sine of amplitude 1, with noise of sd 0.1.
  std::mt19937_64 engine(11);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<double> residuals(150);
  for (std::size_t i = 0; i < residuals.size(); ++i)
    residuals[i] = std::sin(2.0 * std::numbers::pi * static_cast<double>(i) / 150.0) + noise(engine);
  const ResidualCorrelation c = residual_correlation(residuals);
  EXPECT_GT(c.lag1, 0.9);
  EXPECT_TRUE(c.model_leaves_structure());
  EXPECT_GT(c.interval_narrowing(), 4.0);
}

TEST(ResidualCorrelation, TooFewOrConstantResidualsSayNothing) {
  for (const std::vector<double>& residuals : {std::vector<double>{1.0, 2.0}, std::vector<double>(50, 0.3)}) {
    const ResidualCorrelation c = residual_correlation(residuals);
    EXPECT_TRUE(std::isnan(c.lag1));
    EXPECT_FALSE(c.model_leaves_structure());
    EXPECT_EQ(c.interval_narrowing(), 1.0);
  }
  // Few points: the white-noise bound, not kLargeLag1, decides.
  ResidualCorrelation few;
  few.points = 16;
  few.lag1 = 0.9;
  EXPECT_DOUBLE_EQ(few.white_noise_bound(), 1.0);
  EXPECT_FALSE(few.model_leaves_structure());
}

}  // namespace
}  // namespace rover::study
