// The integrator chosen for an accuracy in metres (core/accuracy_choice.hpp):
// it meets the accuracy asked wherever the frontier can, costs less for a
// looser accuracy, and refuses accuracies outside (1e-12, 1e-2) m.
#include "core/accuracy_choice.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace rover {
namespace {

TEST(AccuracyChoice, MeetsTheAccuracyAskedWithValidSettings) {
  // Down to 1e-10 m: the most accurate setting measured is within 3.7e-12 m.
  // A slip tolerance other than the method's default is named.
  for (const double accuracy_m : {5e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10}) {
    const IntegratorChoice c = integrator_for_accuracy(accuracy_m);
    EXPECT_LE(c.measured_error_m, accuracy_m) << c.description;
    std::string why;
    EXPECT_TRUE(c.settings.IsValid(&why)) << why;
    EXPECT_NE(c.description.find(integrator_name(c.settings.method)), std::string::npos) << c.description;
    const bool other_slip = c.settings.slip_tolerance != default_integrator_settings(c.settings.method).slip_tolerance;
    EXPECT_EQ(c.description.find("slip_tol") != std::string::npos, other_slip) << c.description;
  }
}

TEST(AccuracyChoice, LooserAccuracyNeverTightensTheTolerances) {
  // Along the frontier a looser accuracy picks a cheaper setting: never a
  // smaller rtol within one method, never dopri5 after a linearly implicit one.
  IntegratorChoice tighter = integrator_for_accuracy(2e-12);
  for (double accuracy_m = 2e-12; accuracy_m < 1e-2; accuracy_m *= 3.0) {
    const IntegratorChoice c = integrator_for_accuracy(accuracy_m);
    EXPECT_GE(c.measured_error_m, tighter.measured_error_m) << accuracy_m;
    if (c.settings.method == tighter.settings.method) {
      EXPECT_GE(c.settings.relative_tolerance, tighter.settings.relative_tolerance) << accuracy_m;
    }
    EXPECT_FALSE(c.settings.method == IntegratorMethod::kDormandPrince45 &&
                 tighter.settings.method != IntegratorMethod::kDormandPrince45)
        << accuracy_m;
    tighter = c;
  }
}

TEST(AccuracyChoice, DefaultStiffRunServesTheStudiesAccuracy) {
  // 0.05 mm, the studies' target (docs/model.md §9), is met by a setting no
  // tighter than the stiff integrator's defaults.
  const IntegratorChoice c = integrator_for_accuracy(5e-5);
  const IntegratorSettings stiff = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  EXPECT_NE(c.settings.method, IntegratorMethod::kDormandPrince45) << c.description;
  EXPECT_GE(c.settings.relative_tolerance, stiff.relative_tolerance) << c.description;
}

TEST(AccuracyChoice, BeyondTheFrontierSaysSo) {
  const IntegratorChoice c = integrator_for_accuracy(2e-12);
  EXPECT_GT(c.measured_error_m, 2e-12);
  EXPECT_NE(c.description.find("most accurate"), std::string::npos) << c.description;
}

TEST(AccuracyChoice, ExpectedErrorFollowsTheTolerances) {
  // Every chosen setting is expected to meet the accuracy it was chosen for;
  // tightening both tolerances never raises the expected error.
  for (const double accuracy_m : {5e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9}) {
    IntegratorSettings s = integrator_for_accuracy(accuracy_m).settings;
    const std::optional<double> chosen = expected_error_m(s);
    ASSERT_TRUE(chosen.has_value()) << accuracy_m;
    EXPECT_LE(*chosen, accuracy_m);
    s.relative_tolerance /= 10.0;
    s.absolute_tolerance /= 10.0;
    EXPECT_LE(expected_error_m(s).value_or(0.0), *chosen) << accuracy_m;
  }
  // The defaults: the reference within nanometres, the stiff method within
  // the studies' 0.05 mm.
  EXPECT_LE(expected_error_m(default_integrator_settings(IntegratorMethod::kDormandPrince45)).value(), 5e-9);
  const double stiff = expected_error_m(default_integrator_settings(IntegratorMethod::kRosenbrockW)).value();
  EXPECT_GT(stiff, 1e-6);
  EXPECT_LE(stiff, 5e-5);
  // Nothing measured: looser than the loosest setting, or a fixed step.
  IntegratorSettings loose = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  loose.relative_tolerance = 1e-2;
  EXPECT_FALSE(expected_error_m(loose).has_value());
  EXPECT_FALSE(expected_error_m(default_integrator_settings(IntegratorMethod::kRungeKutta4)).has_value());
}

TEST(AccuracyChoice, RefusesAccuraciesOutsideTheRange) {
  for (const double bad : {0.0, -1e-6, 1e-12, 1e-13, 1e-2, 0.5, std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()}) {
    try {
      integrator_for_accuracy(bad);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("1e-12"), std::string::npos) << message;
      EXPECT_NE(message.find("0.01"), std::string::npos) << message;
    }
  }
  try {
    integrator_for_accuracy(0.5);
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("0.5"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rover
