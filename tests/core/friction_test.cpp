// Makkar friction coefficient (core/friction.hpp): the limits and symmetries of
// eq. 8 and its derivative against finite differences.
#include "core/friction.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace rover {
namespace {

// The docs/model.md reference set, and one with a viscous term.
const MakkarGammas kReference{0.9264631218718848, 1831.8163703630614, 1062.6242130578348,
                              0.20009963867985064, 730.7116335954703, 0.0};
const MakkarGammas kViscous{0.5, 2000.0, 900.0, 0.25, 600.0, 0.4};

TEST(MakkarFriction, VanishesAtZeroSlip) {
  EXPECT_EQ(makkar_mu(0.0, kReference), 0.0);
  EXPECT_EQ(makkar_mu(0.0, kViscous), 0.0);
}

TEST(MakkarFriction, SlopeAtZeroIsTheSumOfTheRates) {
  const MakkarGammas& g = kViscous;
  EXPECT_DOUBLE_EQ(makkar_mu_derivative(0.0, g), g[0] * (g[1] - g[2]) + g[3] * g[4] + g[5]);
}

TEST(MakkarFriction, TheJointEvaluationGivesBothValuesExactly) {
  // makkar_mu_and_derivative() shares the tanh of makkar_mu() and
  // makkar_mu_derivative(): the same numbers, bit for bit.
  for (const MakkarGammas& g : {kReference, kViscous}) {
    for (double v : {0.0, 1e-6, 3e-4, 5.5e-4, 2e-3, 0.05, 1.0, -2e-3}) {
      const MakkarMuAndDerivative both = makkar_mu_and_derivative(v, g);
      EXPECT_EQ(both.mu, makkar_mu(v, g)) << "v = " << v;
      EXPECT_EQ(both.d_mu_d_v, makkar_mu_derivative(v, g)) << "v = " << v;
    }
  }
}

TEST(MakkarFriction, IsOddWithAnEvenDerivative) {
  for (const MakkarGammas& g : {kReference, kViscous}) {
    for (double v : {1e-6, 3e-4, 5.5e-4, 2e-3, 0.05, 1.0}) {
      EXPECT_EQ(makkar_mu(-v, g), -makkar_mu(v, g)) << "v = " << v;
      EXPECT_EQ(makkar_mu_derivative(-v, g), makkar_mu_derivative(v, g)) << "v = " << v;
    }
  }
}

TEST(MakkarFriction, DerivativeMatchesCentralDifferences) {
  for (const MakkarGammas& g : {kReference, kViscous}) {
    for (double v = 1e-6; v < 0.1; v *= 1.7) {
      const double h = 1e-4 * v;
      const double numeric = (makkar_mu(v + h, g) - makkar_mu(v - h, g)) / (2.0 * h);
      const double analytic = makkar_mu_derivative(v, g);
      EXPECT_NEAR(analytic, numeric, 1e-6 * (std::abs(analytic) + 1.0)) << "v = " << v;
    }
  }
}

TEST(MakkarFriction, FastSlipTendsToCoulombPlusViscous) {
  // All tanh saturate once g2 v, g3 v, g5 v >> 1: mu -> g4 + g6 v, dmu/dv -> g6.
  for (double v : {0.1, 1.0, 10.0}) {
    EXPECT_NEAR(makkar_mu(v, kViscous), kViscous[3] + kViscous[5] * v, 1e-12);
    EXPECT_NEAR(makkar_mu_derivative(v, kViscous), kViscous[5], 1e-12);
    EXPECT_NEAR(makkar_mu(v, kReference), kReference[3], 1e-12);
  }
}

TEST(MakkarFriction, StribeckHumpRisesAboveTheKineticLevel) {
  // The reference set peaks near mu_s = 0.3 at sub-millimetre speeds and
  // settles at mu_k = g4 ~ 0.2: the curve first rises, then falls.
  EXPECT_GT(makkar_mu_derivative(1e-4, kReference), 0.0);
  EXPECT_LT(makkar_mu_derivative(1.5e-3, kReference), 0.0);
  EXPECT_GT(makkar_mu(6.6e-4, kReference), 0.29);
  EXPECT_NEAR(makkar_mu(0.02, kReference), 0.2, 1e-3);
}

}  // namespace
}  // namespace rover
