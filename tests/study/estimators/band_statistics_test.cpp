// Confidence bands (study/estimators/band_statistics.cpp).
#include "study/estimators/band_statistics.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace rover::study {
namespace {

TEST(BandStatistics, LowerMeanUpperAreOrderedAndMatchNormalTheory) {
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::MatrixXd curves(4000, 3);
  for (Eigen::Index r = 0; r < curves.rows(); ++r) {
    const double x = n(rng);
    curves.row(r) << 1.0 + 0.1 * x, 2.0 - 0.5 * x, 3.0;
  }
  const Band b = band_statistics(curves);
  EXPECT_EQ(b.samples_used, 4000);
  for (int t = 0; t < 3; ++t) {
    EXPECT_LE(b.lower[t], b.mean[t]);
    EXPECT_LE(b.mean[t], b.upper[t]);
    EXPECT_LE(b.p00135[t], b.p99865[t]);
  }
  EXPECT_NEAR(b.mean[0], 1.0, 0.01);
  EXPECT_NEAR(b.std[1], 0.5, 0.02);
  // For normal data the 3-sigma quantiles are close to mean -+ 3 sd.
  EXPECT_NEAR(b.p99865[1], b.upper[1], 0.25);
  // A constant column collapses the band.
  EXPECT_EQ(b.std[2], 0.0);
  EXPECT_EQ(b.lower[2], 3.0);
  EXPECT_EQ(b.upper[2], 3.0);
  EXPECT_EQ(b.p00135[2], 3.0);
}

TEST(BandStatistics, FailedRunsAreLeftOut) {
  Eigen::MatrixXd curves(3, 2);
  curves << 1.0, 2.0, std::nan(""), 100.0, 3.0, 4.0;
  const Band b = band_statistics(curves);
  EXPECT_EQ(b.samples_used, 2);
  EXPECT_DOUBLE_EQ(b.mean[1], 3.0);
}

TEST(BandStatistics, QuantileInterpolatesLikeNumpy) {
  const std::vector<double> v{1.0, 2.0, 3.0, 4.0};
  EXPECT_DOUBLE_EQ(quantile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(quantile(v, 1.0), 4.0);
  EXPECT_DOUBLE_EQ(quantile(v, 0.5), 2.5);
  EXPECT_DOUBLE_EQ(quantile(v, 0.25), 1.75);
}

}  // namespace
}  // namespace rover::study
