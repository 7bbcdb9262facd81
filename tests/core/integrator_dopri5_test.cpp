// Dormand-Prince (core/integrators.cpp) as the reference integrator
// (docs/model.md §9): at rtol 1e-10 it runs through the touchdown of the
// horizontal drop, where the normal force jumps, by accepting one step at
// min_step across each located contact onset, and its result converges as
// the tolerance falls.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/integrators.hpp"
#include "core/simulate.hpp"

namespace rover {
namespace {

// The first 0.3 s of the horizontal drop of docs/model.md §7 (Table 2):
// touchdown at 0.088 s, the impact and the first rebound of the joints.
Scenario horizontal_drop(double relative_tolerance) {
  Scenario s;
  s.name = "drop";
  s.initial_q[coord::z] = 0.281;
  s.initial_q[coord::pitch] = 0.039;
  s.initial_q[coord::roll] = 0.0042;
  s.duration_s = 0.3;
  s.output_rate_hz = 1000.0;
  s.integrator = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  s.integrator.relative_tolerance = relative_tolerance;
  s.integrator.absolute_tolerance = 1e-3 * relative_tolerance;
  return s;
}

double rms_difference_m(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(sum / static_cast<double>(a.size()));
}

TEST(IntegratorDormandPrince, TightToleranceRunsThroughTouchdownAndConverges) {
  const RoverModel model = make_rover_model(default_rover_parameters());
  const ModelInputs inputs = nominal_inputs(model.parameters);
  const Trajectory loose = simulate(model, horizontal_drop(1e-8), inputs);
  const Trajectory middle = simulate(model, horizontal_drop(1e-9), inputs);
  const Trajectory tight = simulate(model, horizontal_drop(1e-10), inputs);
  ASSERT_TRUE(loose.ok()) << loose.message;
  ASSERT_TRUE(middle.ok()) << middle.message;
  ASSERT_TRUE(tight.ok()) << tight.message;
  // The touchdown of the four wheels was met at min_step, not stepped over.
  EXPECT_GE(tight.discontinuity_steps, 1);
  EXPECT_EQ(tight.t.size(), 301u);
  const double loose_m = rms_difference_m(loose.B_l_z, tight.B_l_z);
  const double middle_m = rms_difference_m(middle.B_l_z, tight.B_l_z);
  EXPECT_LT(middle_m, 0.3 * loose_m) << "rtol 1e-9: " << middle_m << " m, rtol 1e-8: " << loose_m << " m";
  EXPECT_LT(loose_m, 1e-6) << "rtol 1e-8 against 1e-10";
}

}  // namespace
}  // namespace rover
