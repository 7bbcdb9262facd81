// Friction synthesis (core/friction_synthesis.hpp): the STEP target of
// docs/model.md §6, the quality measure against the pinned reference set,
// and the fit itself (quality bar, determinism, scaling, resolution rule).
#include "core/friction_synthesis.hpp"

#include <cmath>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>

namespace rover {
namespace {

FrictionParameters engineering(double mu_s, double v_s, double mu_k, double v_k) {
  FrictionParameters p;
  p.mu_static = mu_s;
  p.v_static_mps = v_s;
  p.mu_kinetic = mu_k;
  p.v_kinetic_mps = v_k;
  return p;
}

TEST(FrictionStep, IsTheSmoothCubicBetweenItsEnds) {
  EXPECT_EQ(friction_step(-1.0, 0.0, 2.0, 1.0, 5.0), 2.0);  // clamped below
  EXPECT_EQ(friction_step(0.0, 0.0, 2.0, 1.0, 5.0), 2.0);
  EXPECT_DOUBLE_EQ(friction_step(0.5, 0.0, 2.0, 1.0, 5.0), 3.5);
  EXPECT_EQ(friction_step(1.0, 0.0, 2.0, 1.0, 5.0), 5.0);
  EXPECT_EQ(friction_step(7.0, 0.0, 2.0, 1.0, 5.0), 5.0);  // clamped above
  // Zero slope at both ends.
  const double h = 1e-6;
  EXPECT_NEAR((friction_step(h, 0.0, 2.0, 1.0, 5.0) - 2.0) / h, 0.0, 1e-5);
  EXPECT_NEAR((5.0 - friction_step(1.0 - h, 0.0, 2.0, 1.0, 5.0)) / h, 0.0, 1e-5);
}

TEST(FrictionTarget, PassesThroughTheEngineeringPoints) {
  const FrictionParameters p;  // docs/model.md defaults
  EXPECT_DOUBLE_EQ(friction_target_mu(0.0, p), 0.0);
  EXPECT_DOUBLE_EQ(friction_target_mu(p.v_static_mps, p), p.mu_static);
  EXPECT_DOUBLE_EQ(friction_target_mu(p.v_kinetic_mps, p), p.mu_kinetic);
  EXPECT_DOUBLE_EQ(friction_target_mu(5.0 * p.v_kinetic_mps, p), p.mu_kinetic);
  // Continuous across v_s and v_k, and odd.
  const double eps = 1e-12;
  EXPECT_NEAR(friction_target_mu(p.v_static_mps + eps, p), p.mu_static, 1e-9);
  EXPECT_NEAR(friction_target_mu(p.v_kinetic_mps - eps, p), p.mu_kinetic, 1e-9);
  EXPECT_EQ(friction_target_mu(-3e-4, p), -friction_target_mu(3e-4, p));
  // The maximum is mu_s at v_s.
  for (double v = 0.0; v < 0.02; v += 1e-5) EXPECT_LE(friction_target_mu(v, p), p.mu_static);
}

TEST(FrictionFitQuality, ReproducesTheReferenceNumbersOfModelMd) {
  // docs/model.md: the pinned set has RMS 0.00139 and peak 0.3038 at 0.66 mm/s.
  const FrictionParameters p;
  const FrictionFitQuality q = friction_fit_quality(p.gammas, p);
  EXPECT_NEAR(q.rms, 0.00139, 5e-6);
  EXPECT_NEAR(q.peak_mu, 0.3038, 5e-5);
  EXPECT_NEAR(q.peak_speed_mps, 0.66e-3, 0.005e-3);
  EXPECT_TRUE(q.acceptable);
  // The refined peak is a maximum of mu: the slope (scale g1 g2 ~ 1700 s/m)
  // vanishes there and mu is lower 10 nm/s to either side.
  EXPECT_NEAR(makkar_mu_derivative(q.peak_speed_mps, p.gammas), 0.0,
              1e-5 * p.gammas[0] * p.gammas[1]);
  EXPECT_GE(q.peak_mu, makkar_mu(q.peak_speed_mps - 1e-8, p.gammas));
  EXPECT_GE(q.peak_mu, makkar_mu(q.peak_speed_mps + 1e-8, p.gammas));
}

TEST(FrictionFitQuality, RejectsAPeakOffByMoreThanFivePercent) {
  const FrictionParameters p;
  MakkarGammas high = p.gammas;
  high[0] *= 1.2;  // a taller hump: peak ~ 0.33
  const FrictionFitQuality q = friction_fit_quality(high, p);
  EXPECT_GT(q.peak_mu, 1.05 * p.mu_static);
  EXPECT_FALSE(q.acceptable);
  // Unset (NaN) gammas are never acceptable.
  MakkarGammas unset;
  unset.fill(std::nan(""));
  EXPECT_FALSE(friction_fit_quality(unset, p).acceptable);
}

TEST(FrictionSynthesis, MeetsTheQualityBarForSeveralParameterSets) {
  const FrictionParameters sets[] = {
      FrictionParameters{},                      // docs/model.md defaults
      engineering(0.5, 1e-3, 0.35, 4e-3),
      engineering(0.8, 5.5e-4, 0.6, 2e-3),
  };
  for (const FrictionParameters& p : sets) {
    const MakkarGammas g = synthesize_friction(p);
    for (double gamma : g) EXPECT_GE(gamma, 0.0);
    const FrictionFitQuality q = friction_fit_quality(g, p);
    EXPECT_TRUE(q.acceptable) << "mu_s " << p.mu_static << ": rms " << q.rms << ", peak "
                              << q.peak_mu;
    EXPECT_LT(q.rms, kFrictionMaxRms);
    EXPECT_NEAR(q.peak_mu, p.mu_static, kFrictionMaxPeakError * p.mu_static);
  }
}

TEST(FrictionSynthesis, DefaultFitIsAsGoodAsTheDualAnnealingReference) {
  const FrictionParameters p;
  const double reference_rms = friction_fit_quality(p.gammas, p).rms;
  EXPECT_LE(friction_fit_quality(synthesize_friction(p), p).rms, reference_rms + 1e-5);
}

TEST(FrictionSynthesis, IsDeterministicAcrossCallsAndThreads) {
  const FrictionParameters p = engineering(0.5, 1e-3, 0.35, 4e-3);
  const MakkarGammas first = synthesize_friction(p);
  EXPECT_EQ(synthesize_friction(p), first);
  MakkarGammas in_thread{};
  std::thread worker([&] { in_thread = synthesize_friction(p); });
  worker.join();
  EXPECT_EQ(in_thread, first);
}

TEST(FrictionSynthesis, ScalesWithTheFrictionLevelAndTheSpeeds) {
  // The fit depends only on mu_k / mu_s and v_k / v_s: doubling both
  // coefficients and halving both speeds (exact in binary) scales g1, g4 by 2,
  // the rates g2, g3, g5 by 2 and g6 by 4, bit for bit.
  const FrictionParameters p;
  const FrictionParameters scaled = engineering(2 * p.mu_static, p.v_static_mps / 2,
                                                2 * p.mu_kinetic, p.v_kinetic_mps / 2);
  const MakkarGammas g = synthesize_friction(p);
  const MakkarGammas s = synthesize_friction(scaled);
  const double factor[6] = {2, 2, 2, 2, 2, 4};
  for (int k = 0; k < 6; ++k) EXPECT_EQ(s[k], factor[k] * g[k]) << "gamma " << k + 1;
}

TEST(FrictionSynthesis, SpeedScaledLawIsTheSameCurveOnAShorterAxis) {
  const FrictionParameters p;
  for (const double scale : {0.1, 0.01, 3.0}) {
    const FrictionParameters s = with_friction_speeds_scaled(p, scale);
    EXPECT_DOUBLE_EQ(s.v_static_mps, scale * p.v_static_mps);
    EXPECT_DOUBLE_EQ(s.v_kinetic_mps, scale * p.v_kinetic_mps);
    for (const double v : {0.0, 1e-4, 5.5e-4, 2e-3, 0.05, 1.0})
      EXPECT_NEAR(makkar_mu(scale * v, s.gammas), makkar_mu(v, p.gammas), 1e-14) << "scale " << scale << " v " << v;
    EXPECT_NEAR(makkar_mu_derivative(0.0, s.gammas), makkar_mu_derivative(0.0, p.gammas) / scale,
                1e-12 * makkar_mu_derivative(0.0, s.gammas));
    // Still fitted to its engineering parameters: the simulation keeps it.
    EXPECT_TRUE(friction_fit_quality(s.gammas, s).acceptable) << "scale " << scale;
    EXPECT_EQ(friction_gammas_for(s), s.gammas) << "scale " << scale;
  }
  EXPECT_THROW(with_friction_speeds_scaled(p, 0.0), std::invalid_argument);
  EXPECT_THROW(with_friction_speeds_scaled(p, -1.0), std::invalid_argument);
  EXPECT_THROW(with_friction_speeds_scaled(p, NAN), std::invalid_argument);
}

TEST(FrictionSynthesis, RejectsInconsistentParameters) {
  EXPECT_THROW(synthesize_friction(engineering(0.3, 2e-3, 0.2, 1e-3)), std::invalid_argument);
  EXPECT_THROW(synthesize_friction(engineering(-0.1, 5e-4, 0.2, 2e-3)), std::invalid_argument);
  EXPECT_THROW(synthesize_friction(engineering(0.3, 0.0, 0.2, 2e-3)), std::invalid_argument);
  EXPECT_THROW(friction_fit_quality(FrictionParameters{}.gammas,
                                    engineering(0.3, 5e-4, std::nan(""), 2e-3)),
               std::invalid_argument);
}

// A law whose kinetic level is zero (or nearly) is valid (mu_k >= 0). Its best
// fit sits on a bound of the search (the hump's two rates as close as they
// may be), from which the polish once started a rounding error outside it
// and NLopt refused to run.
TEST(FrictionSynthesis, AZeroKineticLevelIsSynthesised) {
  for (const double mu_k : {0.0, 1e-300}) {
    const FrictionParameters p = engineering(0.3, 5.5e-4, mu_k, 2e-3);
    MakkarGammas g{};
    ASSERT_NO_THROW(g = synthesize_friction(p)) << "mu_k " << mu_k;
    for (double gamma : g) EXPECT_TRUE(std::isfinite(gamma) && gamma >= 0.0) << "mu_k " << mu_k;
    EXPECT_NEAR(friction_fit_quality(g, p).peak_mu, p.mu_static, kFrictionMaxPeakError * p.mu_static);
  }
}

// A law whose gammas do not fit in a double is refused, not returned as infinities.
TEST(FrictionSynthesis, RefusesALawWhoseGammasOverflow) {
  EXPECT_THROW(synthesize_friction(engineering(1e308, 5.5e-4, 0.2, 2e-3)), std::invalid_argument);
}

TEST(FrictionSynthesis, FrictionlessContactGivesZeroGammas) {
  const FrictionParameters p = engineering(0.0, 5e-4, 0.0, 2e-3);
  EXPECT_EQ(synthesize_friction(p), MakkarGammas{});
  EXPECT_TRUE(friction_fit_quality(MakkarGammas{}, p).acceptable);
}

TEST(FrictionGammasFor, KeepsPinnedGammasThatFitAndRefitsOtherwise) {
  const FrictionParameters defaults;
  EXPECT_EQ(friction_gammas_for(defaults), defaults.gammas);

  FrictionParameters changed = defaults;  // still carries the default gammas
  changed.mu_static = 0.5;
  ASSERT_FALSE(friction_fit_quality(changed.gammas, changed).acceptable);
  const MakkarGammas refit = friction_gammas_for(changed);
  EXPECT_NE(refit, changed.gammas);
  EXPECT_TRUE(friction_fit_quality(refit, changed).acceptable);

  // A small change that the pinned set would still pass must change the model.
  FrictionParameters nudged = defaults;
  nudged.mu_static = 0.305;
  ASSERT_TRUE(friction_fit_quality(nudged.gammas, nudged).acceptable);
  const MakkarGammas nudged_fit = friction_gammas_for(nudged);
  EXPECT_NE(nudged_fit, defaults.gammas);
  EXPECT_GT(makkar_mu(6.6e-4, nudged_fit), makkar_mu(6.6e-4, defaults.gammas));

  FrictionParameters unset = defaults;  // a config without gammas
  unset.gammas.fill(std::nan(""));
  EXPECT_TRUE(friction_fit_quality(friction_gammas_for(unset), unset).acceptable);
}

}  // namespace
}  // namespace rover
