// Scenario helpers (core/scenario.cpp): the output grid of docs/model.md §8
// must end at duration_s even where duration / period rounds just below an
// integer in floating point (0.7 s at 1 kHz: 699.9999999999999 periods).
#include "core/scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace rover {
namespace {

Scenario scenario_of(double duration_s, double output_rate_hz) {
  Scenario s;
  s.duration_s = duration_s;
  s.output_rate_hz = output_rate_hz;
  return s;
}

TEST(Scenario, OutputSamplesRunFromZeroToTheDuration) {
  EXPECT_EQ(output_sample_count(scenario_of(1.0, 1000.0)), 1001u);
  EXPECT_EQ(output_sample_count(scenario_of(0.7, 1000.0)), 701u);
  EXPECT_EQ(output_sample_count(scenario_of(2.3, 300.0)), 691u);
  EXPECT_EQ(output_sample_count(scenario_of(0.25, 1000.0)), 251u);
}

TEST(Scenario, AnOutputGridThatDoesNotReachTheDurationStopsBeforeIt) {
  // 1 s at 3 Hz: samples at 0, 1/3, 2/3 and 1 s; at 0.9 s the last is 2/3.
  EXPECT_EQ(output_sample_count(scenario_of(1.0, 3.0)), 4u);
  EXPECT_EQ(output_sample_count(scenario_of(0.9, 3.0)), 3u);
}

bool valid(const IntegratorSettings& s, std::string* why) { return s.IsValid(why); }

TEST(IntegratorSettings, DefaultsOfEveryMethodAreValid) {
  for (const IntegratorMethod m :
       {IntegratorMethod::kDormandPrince45, IntegratorMethod::kRungeKutta4, IntegratorMethod::kRosenbrockW}) {
    std::string why = "untouched";
    EXPECT_TRUE(default_integrator_settings(m).IsValid(&why)) << why;
    EXPECT_EQ(why, "untouched");
  }
  EXPECT_TRUE(default_integrator_settings(IntegratorMethod::kDormandPrince45).IsValid(nullptr));
}

TEST(IntegratorSettings, BadValuesAreNamedWithReadableNumbers) {
  std::string why;
  IntegratorSettings s = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  s.absolute_tolerance = 0.0;
  EXPECT_FALSE(valid(s, &why));
  EXPECT_NE(why.find("atol"), std::string::npos) << why;
  s = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  s.relative_tolerance = std::nan("");
  EXPECT_FALSE(valid(s, &why));
  EXPECT_NE(why.find("rtol"), std::string::npos) << why;
  // min_step above initial_step: the numbers as written, not 0.000000.
  s = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  s.min_step_s = 1e-12;
  s.initial_step_s = 1e-13;
  EXPECT_FALSE(valid(s, &why));
  EXPECT_NE(why.find("1e-12 <= 1e-13"), std::string::npos) << why;
  EXPECT_EQ(why.find("0.000000"), std::string::npos) << why;
  s = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  s.max_step_s = 1e-6;  // below initial_step 1e-5
  EXPECT_FALSE(valid(s, &why));
  s = default_integrator_settings(IntegratorMethod::kRungeKutta4);
  s.fixed_step_s = -1e-5;
  EXPECT_FALSE(valid(s, &why));
  EXPECT_NE(why.find("-1e-05"), std::string::npos) << why;
  // RK4 ignores the adaptive fields; dopri5 ignores fixed_step.
  s.fixed_step_s = 1e-5;
  s.absolute_tolerance = -1.0;
  EXPECT_TRUE(valid(s, &why)) << why;
  s = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  s.fixed_step_s = 0.0;
  EXPECT_TRUE(valid(s, &why)) << why;
}

TEST(IntegratorSettings, SlipToleranceIsAFractionOfTheFrictionSpeedScale) {
  // The stiff methods hold a slip-speed error to a fraction in (0, 1] of the
  // speed on which the friction force changes; dopri5 has no such test.
  std::string why;
  for (const IntegratorMethod m : {IntegratorMethod::kRosenbrockW, IntegratorMethod::kRodas4}) {
    IntegratorSettings s = default_integrator_settings(m);
    EXPECT_GT(s.slip_tolerance, 0.0);
    EXPECT_LE(s.slip_tolerance, IntegratorSettings::kMaxSlipTolerance);
    s.slip_tolerance = 1.0;
    EXPECT_TRUE(valid(s, &why)) << why;
    for (const double bad : {0.0, -0.01, 1.5, std::nan("")}) {
      s.slip_tolerance = bad;
      EXPECT_FALSE(valid(s, &why)) << bad;
      EXPECT_NE(why.find("slip_tol"), std::string::npos) << why;
    }
    s.slip_tolerance = 1.5;
    valid(s, &why);
    EXPECT_NE(why.find("1.5"), std::string::npos) << why;
  }
  IntegratorSettings s = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  s.slip_tolerance = 0.0;
  EXPECT_TRUE(valid(s, &why)) << why;
}

TEST(Scenario, Rk4StepMustDivideTheOutputPeriod) {
  Scenario s = scenario_of(1.0, 1000.0);
  s.integrator = default_integrator_settings(IntegratorMethod::kRungeKutta4);
  std::string why;
  for (const double step : {1e-3, 2e-5, 1e-5, 1e-3 / 7.0}) {
    s.integrator.fixed_step_s = step;
    EXPECT_TRUE(scenario_is_valid(s, &why)) << step << ": " << why;
  }
  for (const double step : {0.5, 3e-5, 2e-3}) {
    s.integrator.fixed_step_s = step;
    EXPECT_FALSE(scenario_is_valid(s, &why)) << step;
    EXPECT_NE(why.find("does not divide the output period 0.001 s"), std::string::npos) << why;
  }
  s.integrator.fixed_step_s = 1e-5;
  s.output_rate_hz = 0.0;
  EXPECT_FALSE(scenario_is_valid(s, &why));
  EXPECT_NE(why.find("output rate"), std::string::npos) << why;
}

}  // namespace
}  // namespace rover
