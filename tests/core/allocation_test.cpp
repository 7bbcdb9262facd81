// The right-hand side allocates nothing (core/equations_of_motion.hpp): every
// heap allocation of this test program goes through the replaced global
// operator new below, which counts the allocations made on its own thread.
// The counter is checked against a call that must allocate (a std::vector),
// so the test cannot pass because nothing is counted.
#include <gtest/gtest.h>

#include <cstdlib>
#include <new>
#include <vector>

#include "core/drive_kinematics.hpp"
#include "core/equations_of_motion.hpp"
#include "core/integrators.hpp"
#include "model_fixtures.hpp"

namespace {
thread_local long allocations_on_this_thread = 0;
}  // namespace

void* operator new(std::size_t size) {
  ++allocations_on_this_thread;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace rover {
namespace {

// Allocations made by f() on this thread.
template <class F>
long allocations_of(F&& f) {
  const long before = allocations_on_this_thread;
  f();
  return allocations_on_this_thread - before;
}

TEST(Allocation, TheCounterSeesAnAllocation) {
  EXPECT_GE(allocations_of([] {
              std::vector<double> v(100, 1.0);
              EXPECT_EQ(v.size(), 100u);
            }),
            1);
}

StateVector touching_state(std::uint32_t seed, double height_m) {
  std::mt19937 rng(seed);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  q[coord::z] = height_m;
  StateVector x;
  x << q, u;
  return x;
}

TEST(Allocation, RightHandSideOnFlatGroundAllocatesNothing) {
  const RoverModel model = make_rover_model(default_rover_parameters());
  const ModelInputs inputs = nominal_inputs(model.parameters);
  const StateVector x = touching_state(3, 0.21);
  DynamicsWorkspace workspace;
  StateVector dx = StateVector::Zero();
  EXPECT_EQ(allocations_of([&] { dx = state_derivative(model, workspace, inputs, x); }), 0);
  int touching = 0;
  for (const WheelContacts& w : workspace.contacts) touching += w.count;
  EXPECT_GT(touching, 0);  // the contact code ran
  EXPECT_TRUE(dx.allFinite());
}

TEST(Allocation, RightHandSideOnAHeightGridAllocatesNothing) {
  const HeightGrid grid = testing::sampled_grid(-2.0, -2.0, 0.05, 0.05, 81, 81, [](double x, double y) {
    return 0.03 * std::sin(3.0 * x) * std::cos(2.0 * y);
  });
  const RoverModel model = make_rover_model(default_rover_parameters(), Terrain::from_grid(grid));
  const ModelInputs inputs = nominal_inputs(model.parameters);
  const StateVector x = touching_state(5, 0.22);
  DynamicsWorkspace workspace;
  StateVector dx = StateVector::Zero();
  EXPECT_EQ(allocations_of([&] { dx = state_derivative(model, workspace, inputs, x); }), 0);
  int touching = 0;
  for (const WheelContacts& w : workspace.contacts) touching += w.count;
  EXPECT_GT(touching, 0);
  EXPECT_TRUE(dx.allFinite());
}

// With a drive schedule (three segments, ramps between them, a mode change),
// in a steady stretch and inside both ramps.
TEST(Allocation, RightHandSideWithADriveScheduleAllocatesNothing) {
  const RoverModel model = make_rover_model(default_rover_parameters());
  const ModelInputs inputs = nominal_inputs(model.parameters);
  DriveScheduleOptions options;
  options.ramp_time_s = 0.2;
  const CompiledDriveSchedule schedule(make_drive_kinematics(model.parameters),
                                       {{0.0, DriveMode::kSymmetricAckermann, {0.3, 0.0, 0.0}},
                                        {1.0, DriveMode::kSymmetricAckermann, {0.3, 0.0, 0.4}},
                                        {2.0, DriveMode::kParallel, {0.2, 0.1, 0.0}}},
                                       options);
  const OdeSystem system{model, inputs, &schedule};
  const StateVector x = touching_state(3, 0.21);
  DynamicsWorkspace workspace;
  for (const double t : {0.5, 1.1, 2.05, 2.5}) {
    StateVector dx = StateVector::Zero();
    EXPECT_EQ(allocations_of([&] { dx = ode_derivative(system, workspace, t, x); }), 0) << "t " << t;
    EXPECT_TRUE(dx.allFinite());
  }
  // The schedule is in force: the set-points differ between the stretches.
  EXPECT_NE(system.inputs_at(0.5).wheel_speed_ref_radps, system.inputs_at(2.5).wheel_speed_ref_radps);
  EXPECT_NE(system.inputs_at(1.1).steer_ref_rad, system.inputs_at(1.5).steer_ref_rad);
}

}  // namespace
}  // namespace rover
