// Time integrators of the first-order system x = [q; u] (docs/model.md §9).
// Each integrator advances one OdeSystem from t = 0, hands the state at every
// requested sample time to a recorder, and stops early on trouble (non-finite
// state, step-size underflow, wall-time budget), reporting why.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/coordinates.hpp"
#include "core/equations_of_motion.hpp"
#include "core/model_inputs.hpp"
#include "core/rover_model.hpp"
#include "core/scenario.hpp"

namespace rover {

// The system being integrated: the model and its inputs, with the actuator
// set-points of a drive schedule at time t if the scenario has one. Read-only;
// each integrator evaluates it in its own DynamicsWorkspace and counts the
// evaluations in its own report.
struct OdeSystem {
  const RoverModel& model;
  const ModelInputs& inputs;
  const CompiledDriveSchedule* drive_schedule = nullptr;  // nullptr: constant set-points of `inputs`
  // The model inputs in force at time t.
  ModelInputs inputs_at(double t) const;
};

// dx/dt of `system` at (t, x), computed in `workspace` without forming M
// (state_derivative_articulated()).
StateVector ode_derivative(const OdeSystem& system, DynamicsWorkspace& workspace, double t,
                           const StateVector& x);

struct IntegrationRequest {
  double sample_period_s = 1e-3;
  std::size_t sample_count = 1;  // samples at k * period, k = 0 .. count-1 (sample 0 is x0)
  std::function<void(double t, const StateVector& x)> record;
  std::function<bool()> out_of_time;            // wall-time budget check
  std::function<void(double t)> progress;       // optional, called now and then
};

// How a run ended; simulate() reports the integrator's status as it is.
// kInvalidScenario: the scenario cannot run on this model (a drive schedule a
// mode cannot serve, invalid integrator settings); nothing was integrated.
enum class SimulationStatus {
  kOk = 0,
  kNonFinite = 1,
  kStepSizeUnderflow = 2,
  kTimeBudgetExceeded = 3,
  kInvalidScenario = 4,
  kStepSizeCollapsed = 5  // the run could not progress (see StallWatch)
};
const char* status_name(SimulationStatus status);

struct IntegrationReport {
  SimulationStatus status = SimulationStatus::kOk;
  double failed_at_s = 0.0;
  std::string detail;
  long steps = 0;
  long rhs_evaluations = 0;  // right-hand sides (and, for rosenbrock, Jacobian assemblies)
  long rejected_steps = 0;   // tries that failed the error test or missed a contact onset
  long discontinuity_steps = 0;  // dopri5: steps accepted at min_step across a contact jump
  double min_step_s = 0.0, max_step_s = 0.0;
};

// Detects a run whose step size has collapsed, which would otherwise crawl
// until its wall-time budget is gone. A run has collapsed when
//  * kWindowSteps accepted steps advanced the time by less than
//    kWindowFraction of the duration (at that pace the run would need more
//    than kWindowSteps / kWindowFraction = 1e9 steps), or
//  * a step is shorter than kRoundingUnits rounding units of the time,
//    kRoundingUnits eps max(t, duration), where t + h hardly differs from t.
// The window belongs to one integration (one per run, not shared).
struct StallWatch {
  static constexpr long kWindowSteps = 100000;
  static constexpr double kWindowFraction = 1e-4;
  static constexpr double kRoundingUnits = 64.0;
  long window_start_step = 0;
  double window_start_t_s = 0.0;
};

// Bookkeeping shared by every integrator after an accepted step of length h
// ending at t: counts it, tracks the extreme step sizes, and returns true (with
// the status filled in) if the state is not finite, the step size has
// collapsed (`stall`) or the wall-time budget is used up.
bool step_is_bad(IntegrationReport& report, StallWatch& stall, double t, double h,
                 const StateVector& x, const IntegrationRequest& request);

IntegrationReport integrate_dormand_prince(const OdeSystem& system, StateVector x,
                                           const IntegratorSettings& settings,
                                           const IntegrationRequest& request);
IntegrationReport integrate_rk4(const OdeSystem& system, StateVector x,
                                const IntegratorSettings& settings, const IntegrationRequest& request);
// Linearly implicit Rosenbrock-W (ROS34PW2) with analytic derivatives of the
// stiff force elements; adaptive like Dormand-Prince, with the same settings
// (core/integrator_rosenbrock.cpp). The Jacobian assembly of each step is
// counted as one right-hand-side evaluation. settings.method kRodas4 runs the
// fourth-order RODAS4 on the same machinery instead (rosenbrock_w.hpp).
IntegrationReport integrate_rosenbrock(const OdeSystem& system, StateVector x,
                                       const IntegratorSettings& settings,
                                       const IntegrationRequest& request);

// Dispatches on settings.method.
IntegrationReport integrate(const OdeSystem& system, const StateVector& x0,
                            const IntegratorSettings& settings, const IntegrationRequest& request);

}  // namespace rover
