#include "study/studies/surface.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace rover::study {
namespace {

TEST(Surface, LinearRegressionOfAnExactLine) {
  const LinearFit r = linear_regression({1e2, 1e3, 1e4, 1e5}, {0.5 + 2e-5 * 1e2, 0.5 + 2e-5 * 1e3,
                                                              0.5 + 2e-5 * 1e4, 0.5 + 2e-5 * 1e5});
  EXPECT_NEAR(r.intercept, 0.5, 1e-12);
  EXPECT_NEAR(r.slope, 2e-5, 1e-17);
  EXPECT_NEAR(r.r_squared, 1.0, 1e-12);
}

TEST(Surface, LinearRegressionOfOnePointIsUndefined) {
  const LinearFit r = linear_regression({1e2}, {0.5});
  EXPECT_TRUE(std::isnan(r.intercept));
  EXPECT_TRUE(std::isnan(r.slope));
}

TEST(Surface, LinearRegressionOfTwoPointsHasNoRSquared) {
  // Two points lie on their line whatever they are: r^2 would be 1 by
  // construction, so it is not given.
  const LinearFit r = linear_regression({1e2, 1e4}, {0.3, 0.9});
  EXPECT_NEAR(r.slope, 0.6 / 9.9e3, 1e-15);
  EXPECT_TRUE(std::isnan(r.r_squared));
  // Three points off a line: r^2 below 1, the squared correlation.
  const LinearFit three = linear_regression({0.0, 1.0, 2.0}, {0.0, 1.0, 0.5});
  EXPECT_NEAR(three.r_squared, 0.25, 1e-12);  // cov 0.25, var_x 1, var_y 0.25 (population sums)
}

}  // namespace
}  // namespace rover::study
