// Sines and cosines of many angles at once (core/sine_cosine.hpp): within
// two units in the last place of std::sin and std::cos over joint angles,
// many turns of a wheel and the quadrant boundaries; exact where it must be
// (0, the sign of an odd function); and angles beyond the reduced range or
// not finite as std::sin and std::cos give them.
#include "core/sine_cosine.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace rover {
namespace {

constexpr std::size_t kBatch = 24;

// |a - b| in units of the last place of b (at least the smallest normal's).
double ulps_apart(double a, double b) {
  const double ulp = std::max(std::abs(std::nextafter(b, 2.0 * b + 1.0) - b), std::numeric_limits<double>::min());
  return std::abs(a - b) / ulp;
}

void expect_like_libm(const std::array<double, kBatch>& angles) {
  SinesCosines<kBatch> out;
  sines_and_cosines(angles, out);
  for (std::size_t i = 0; i < kBatch; ++i) {
    const double x = angles[i];
    // Where sin or cos is near zero its last place is tiny: measured
    // against an ulp of 1 there (the reduction's absolute error).
    const auto close = [](double value, double reference) {
      return ulps_apart(value, reference) <= 2.0 || std::abs(value - reference) <= 2.5e-16;
    };
    EXPECT_TRUE(close(out.sin[i], std::sin(x))) << "sin(" << x << ") = " << out.sin[i] << ", libm " << std::sin(x);
    EXPECT_TRUE(close(out.cos[i], std::cos(x))) << "cos(" << x << ") = " << out.cos[i] << ", libm " << std::cos(x);
  }
}

TEST(SineCosine, AgreesWithLibmOverJointAnglesAndWheelTurns) {
  std::mt19937 rng(7);
  for (const double range : {0.1, 1.0, 4.0, 100.0, 1e4, 9e5}) {
    std::uniform_real_distribution<double> angle(-range, range);
    for (int trial = 0; trial < 2000; ++trial) {
      std::array<double, kBatch> angles;
      for (double& a : angles) a = angle(rng);
      expect_like_libm(angles);
    }
  }
}

TEST(SineCosine, AgreesWithLibmAtQuadrantBoundaries) {
  std::array<double, kBatch> angles;
  for (int k = -4; k <= 4; ++k) {
    const double boundary = k * std::numbers::pi / 4.0;
    for (std::size_t i = 0; i < kBatch; ++i) {
      const double step = static_cast<double>(static_cast<int>(i) - 12);
      angles[i] = boundary + step * 1e-16 * std::max(1.0, std::abs(boundary));
    }
    expect_like_libm(angles);
  }
}

TEST(SineCosine, ExactAtZeroAndOdd) {
  std::array<double, kBatch> angles{}, negated{};
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-50.0, 50.0);
  for (std::size_t i = 1; i < kBatch; ++i) angles[i] = angle(rng);
  for (std::size_t i = 0; i < kBatch; ++i) negated[i] = -angles[i];
  SinesCosines<kBatch> out, out_negated;
  sines_and_cosines(angles, out);
  sines_and_cosines(negated, out_negated);
  EXPECT_EQ(out.sin[0], 0.0);
  EXPECT_EQ(out.cos[0], 1.0);
  for (std::size_t i = 0; i < kBatch; ++i) {
    EXPECT_EQ(out_negated.sin[i], -out.sin[i]) << angles[i];
    EXPECT_EQ(out_negated.cos[i], out.cos[i]) << angles[i];
  }
}

TEST(SineCosine, HugeAndNonFiniteAnglesGoToLibm) {
  std::array<double, kBatch> angles{};
  angles[1] = 2.0 * kLargestReduced_rad;
  angles[2] = -1e300;
  angles[3] = std::numeric_limits<double>::infinity();
  angles[4] = std::numeric_limits<double>::quiet_NaN();
  angles[5] = 0.5;
  SinesCosines<kBatch> out;
  sines_and_cosines(angles, out);
  for (int i = 1; i <= 2; ++i) {
    EXPECT_EQ(out.sin[i], std::sin(angles[i]));
    EXPECT_EQ(out.cos[i], std::cos(angles[i]));
  }
  for (int i = 3; i <= 4; ++i) {
    EXPECT_TRUE(std::isnan(out.sin[i]));
    EXPECT_TRUE(std::isnan(out.cos[i]));
  }
  EXPECT_LE(ulps_apart(out.sin[5], std::sin(0.5)), 2.0);
}

}  // namespace
}  // namespace rover
