// A simulation scenario (docs/model.md §7): initial state, actuator
// set-points, duration, output rate and integrator settings. The terrain is
// part of the RoverModel; the file formats live in io/scenario_config.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "core/coordinates.hpp"
#include "core/drive_kinematics.hpp"
#include "core/rover_parameters.hpp"

namespace rover {

enum class IntegratorMethod {
  kDormandPrince45,  // explicit Runge-Kutta 5(4), adaptive, dense output (default)
  kRungeKutta4,      // the paper's classic fixed-step RK4
  kRosenbrockW,      // linearly implicit Rosenbrock-W ROS34PW2 for the stiff forces
  kRodas4,           // linearly implicit Rosenbrock RODAS4 (order 4), same Jacobian and control
};

const char* integrator_name(IntegratorMethod method);
IntegratorMethod integrator_from_name(const std::string& name);  // throws std::invalid_argument

struct IntegratorSettings {
  IntegratorMethod method = IntegratorMethod::kDormandPrince45;
  double relative_tolerance = 1e-6;
  double absolute_tolerance = 1e-9;
  double initial_step_s = 1e-5;      // adaptive: first trial step
  double min_step_s = 1e-12;         // adaptive: below this the run fails
  double max_step_s = 1e-2;          // adaptive: upper bound on the step
  double fixed_step_s = 1e-5;        // RK4: step; must divide the output period
  // rosenbrock, rodas4: a contact's slip-speed error is held to this fraction
  // of the speed on which its friction force changes (integrator_rosenbrock.cpp);
  // smaller buys the accuracy of the drops' compression where atol does not
  // (docs/performance.md, "Accuracy against cost").
  double slip_tolerance = 0.05;

  // Tolerances beyond these say nothing about the result (an rtol of 1 lets
  // every state be wrong by its own size; an atol above 1 cm is larger than
  // the deflections studied) or ask for less than round-off.
  static constexpr double kMinRelativeTolerance = 1e-14, kMaxRelativeTolerance = 0.1;
  // An atol below 1e-18 m is below the round-off of every state at the
  // rover's scale (a 0.3 m height resolves 6e-17 m): the step size collapses.
  static constexpr double kMinAbsoluteTolerance = 1e-18, kMaxAbsoluteTolerance = 1e-2;
  // A slip tolerance of the whole speed scale lets the friction force be
  // wrong by its whole range.
  static constexpr double kMaxSlipTolerance = 1.0;

  // Ceres-style check of the fields the method uses: tolerances within the
  // limits above (slip_tolerance in (0, kMaxSlipTolerance] for rosenbrock and
  // rodas4) and 0 < min_step <= initial_step <= max_step for the adaptive
  // methods, a finite fixed_step > 0 for RK4. On failure, says why in `why`
  // (if not null), with the numbers as written (1e-12, not 0.000000).
  bool IsValid(std::string* why) const;
};

// The settings a method is meant to run with: the defaults above for dopri5
// and rk4; for rosenbrock, whose error estimate is that of its embedded
// second-order solution, rtol 1e-5 and atol 2e-4, which keep B_l z of both
// drop tests within 0.03 mm RMS of dopri5 at rtol 1e-8 for f = 1e2 .. 1e4
// and v_s down to 1/100 of its default, over several preload sets (
// the target is 0.05 mm); at f = 1e5 the skewed drop is 0.02-0.07 mm off
// (docs/performance.md, "Stiff integration"). See core/integrator_rosenbrock.cpp.
IntegratorSettings default_integrator_settings(IntegratorMethod method);

// A time-varying driving command: piecewise body-velocity commands in a
// driving mode, turned into d_ref and w_ref by core/drive_kinematics. Only the
// commands: simulate() compiles them (CompiledDriveSchedule) against the drive
// kinematics of the model it runs, so a study that changes the rover (the
// wheel radius, say) gets wheel commands for that rover.
struct DriveSchedule {
  std::vector<DriveCommandSegment> segments;  // empty: constant set-points
  DriveScheduleOptions options;
};

struct Scenario {
  std::string name;
  Coordinates initial_q = Coordinates::Zero();
  Coordinates initial_u = Coordinates::Zero();
  std::array<double, kNumLegs> wheel_speed_ref_radps{};
  std::array<double, kNumLegs> steer_ref_rad{};
  double duration_s = 1.0;
  double output_rate_hz = 1000.0;
  IntegratorSettings integrator;
  double wall_time_budget_s = 3600.0;  // a run taking longer is stopped and reported
  DriveSchedule drive;                 // optional; overrides the set-points above
};

// The scenario's own numbers: finite positive duration, output rate and
// wall-time budget, valid integrator settings, and for RK4 a step that divides
// the output period (to 1e-9 relative): the step run is the step recorded.
// simulate() returns kInvalidScenario for a scenario that fails this.
bool scenario_is_valid(const Scenario& scenario, std::string* why);

// The number of output samples of a scenario, t_k = k / output_rate_hz for
// k = 0 .. count-1, the last at duration_s (to rounding).
std::size_t output_sample_count(const Scenario& scenario);

}  // namespace rover
