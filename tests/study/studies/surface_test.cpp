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

}  // namespace
}  // namespace rover::study
