// The pure simulation function the study layer calls thousands of times
// (docs/model.md §7–9): integrates the equations of motion of a scenario
// with given (f, c_q, M0) and returns the sampled trajectory and its outputs.
//
// simulate() has no side effects and shares nothing mutable: many threads may
// call it at once with the same RoverModel. A run that blows up (non-finite
// state, step size underflow or collapse, wall-time budget exceeded) or cannot
// start (scenario_is_valid() fails, a drive schedule the model cannot serve)
// returns a status and a message; it never throws for numerical trouble, and
// never hangs.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/integrators.hpp"
#include "core/model_inputs.hpp"
#include "core/rover_model.hpp"
#include "core/scenario.hpp"

namespace rover {

// The inputs simulate() runs with: (f, c_q, M0) from `inputs`, the constant
// actuator set-points from `scenario` (a drive schedule overrides them in time).
ModelInputs model_inputs_for(const Scenario& scenario, const ModelInputs& inputs);

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Output samples (docs/model.md §8), one row per sample time.
struct Trajectory {
  SimulationStatus status = SimulationStatus::kOk;
  std::string message;
  std::vector<double> t;
  RowMatrix q, u;                    // samples x 23
  std::vector<double> B_l_z, B_r_z, G_z, pitch, roll;
  RowMatrix normal_force_N;          // samples x 4, total per wheel
  double wall_time_s = 0.0;
  long rhs_evaluations = 0;
  long steps = 0;
  double min_step_s = 0.0, max_step_s = 0.0;
  bool ok() const { return status == SimulationStatus::kOk; }
};

struct SimulationObserver {
  // Called now and then with the simulated time (progress on long runs).
  std::function<void(double t_s)> progress;
};

// (f, c_q, M0) come from `inputs`; its set-points are replaced by those of
// the scenario (model_inputs_for) and, in time, by its drive schedule.
Trajectory simulate(const RoverModel& model, const Scenario& scenario,
                    const ModelInputs& inputs, const SimulationObserver& observer = {});

}  // namespace rover
