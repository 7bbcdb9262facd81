// Preload sampling and grids (study/design/sampling.cpp).
#include "study/design/design.hpp"
#include "study/design/sampling.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace rover::study {
namespace {

TEST(Sampling, SampleDependsOnlyOnSeedAndIndex) {
  const SStructureParameters s;
  EXPECT_EQ(sample_preloads(s, 42, 7), sample_preloads(s, 42, 7));
  EXPECT_NE(sample_preloads(s, 42, 7), sample_preloads(s, 42, 8));
  EXPECT_NE(sample_preloads(s, 43, 7), sample_preloads(s, 42, 7));
  // Drawing others first changes nothing (no shared engine).
  for (int i = 0; i < 100; ++i) sample_preloads(s, 42, static_cast<std::uint64_t>(i));
  EXPECT_EQ(sample_preloads(s, 42, 7), sample_preloads(s, 42, 7));
}

TEST(Sampling, DrawsHaveTheConfiguredMeanAndStandardDeviation) {
  const SStructureParameters s;
  const int n = 20000;
  std::array<double, kNumSJoints> sum{}, sum2{};
  for (int i = 0; i < n; ++i) {
    const auto m = sample_preloads(s, 1, static_cast<std::uint64_t>(i));
    for (int j = 0; j < kNumSJoints; ++j) {
      sum[j] += m[j];
      sum2[j] += m[j] * m[j];
    }
  }
  for (int j = 0; j < kNumSJoints; ++j) {
    const double mean = sum[j] / n, sd = std::sqrt(sum2[j] / n - mean * mean);
    // 5 standard errors.
    EXPECT_NEAR(mean, s.preload_mean_Nm[j], 5 * s.preload_sd_Nm[j] / std::sqrt(n)) << j;
    EXPECT_NEAR(sd, s.preload_sd_Nm[j], 5 * s.preload_sd_Nm[j] / std::sqrt(2.0 * n)) << j;
  }
}

TEST(Sampling, ZeroScaleGivesTheMeans) {
  const SStructureParameters s;
  EXPECT_EQ(sample_preloads(s, 3, 5, 0.0), s.preload_mean_Nm);
}

TEST(Sampling, GridsIncludeBothEnds) {
  const auto lin = linear_grid(0.05, 0.5, 6);
  ASSERT_EQ(lin.size(), 6u);
  EXPECT_DOUBLE_EQ(lin.front(), 0.05);
  EXPECT_DOUBLE_EQ(lin.back(), 0.5);
  EXPECT_NEAR(lin[1] - lin[0], 0.09, 1e-15);
  const auto lg = log_grid(1e2, 1e5, 4);
  EXPECT_EQ(lg, (std::vector<double>{1e2, 1e3, 1e4, 1e5}));
  EXPECT_THROW(log_grid(0.0, 1.0, 3), std::invalid_argument);
  EXPECT_THROW(linear_grid(0.0, 1.0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace rover::study
