// Time-offset handling of the calibration (study/calibration.cpp) and the
// regression of the response-surface sweep (study/surface.cpp).
#include "study/calibration.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "study/surface.hpp"

namespace rover::study {
namespace {

TEST(Calibration, BestOffsetRecoversAKnownShift) {
  // A drop-like curve: constant, a smooth dip, constant.
  std::vector<double> t, z;
  for (int k = 0; k <= 1000; ++k) {
    t.push_back(k * 1e-3);
    z.push_back(0.25 - 0.05 * std::exp(-std::pow((t.back() - 0.3) / 0.08, 2)));
  }
  const double offset = 0.0437;
  std::vector<double> td, zd;
  for (int k = 0; k <= 400; ++k) {
    td.push_back(k * 2.5e-3);
    zd.push_back(0.25 - 0.05 * std::exp(-std::pow((td.back() - offset - 0.3) / 0.08, 2)));
  }
  const double found = best_offset(t, z, td, zd, -0.2, 0.2);
  EXPECT_NEAR(found, offset, 2e-5);
  EXPECT_LT(shifted_rms(t, z, td, zd, found), 1e-5);
  EXPECT_GT(shifted_rms(t, z, td, zd, 0.0), 1e-3);
}

TEST(Surface, LinearRegressionOfAnExactLine) {
  const auto r = linear_regression({1e2, 1e3, 1e4, 1e5}, {0.5 + 2e-5 * 1e2, 0.5 + 2e-5 * 1e3,
                                                         0.5 + 2e-5 * 1e4, 0.5 + 2e-5 * 1e5});
  EXPECT_NEAR(r[0], 0.5, 1e-12);
  EXPECT_NEAR(r[1], 2e-5, 1e-17);
  EXPECT_NEAR(r[2], 1.0, 1e-12);
}

}  // namespace
}  // namespace rover::study
