// The pure simulation function the study layer calls thousands of times
// (docs/model.md §7–9): integrates the equations of motion of a scenario
// with given (f, c_q, M0) and returns the sampled trajectory and its outputs.
//
// simulate() has no side effects and shares nothing mutable: many threads may
// call it at once with the same RoverModel. A run that blows up (non-finite
// state, step size underflow or collapse, wall-time budget exceeded or sure to
// be exceeded: RunPaceWatch) or cannot start (scenario_is_valid() fails, a
// drive schedule the model cannot serve) returns a status and a message; it
// never throws for numerical trouble, and never hangs. A run whose observer's
// stop flag is raised ends at its next step with SimulationStopped.
#pragma once

#include <atomic>
#include <functional>
#include <stdexcept>
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
  long rejected_steps = 0;       // tries that failed (IntegrationReport)
  long discontinuity_steps = 0;  // dopri5 steps at min_step across a contact jump
  double min_step_s = 0.0, max_step_s = 0.0;
  bool ok() const { return status == SimulationStatus::kOk; }
};

// The projected-cost check of simulate(): a run whose pace says it cannot
// finish within its wall-time budget (a rover at 1e8 m/s crawls through
// nanosecond steps) is stopped after seconds, not after the whole budget.
//
// Time is the run's compute time (simulate() feeds it the CPU time of its
// thread), so a run starved by a loaded machine is never judged by the
// seconds it did not get; since wall time is at least compute time, a run
// whose compute time alone exceeds the budget cannot finish within it. The
// pace is the simulated time advanced per second of compute over a recent
// window: the window's start moves to the previous mark each time the elapsed
// compute time doubles (marks at 1, 2, 4, 8 ... s), so the pace is measured
// over at least the last half of the run and a slow start (the first steps, a
// landing) is forgotten. Nothing is projected before kGraceWall_s. A run is
// hopeless when the projected total, elapsed + (duration - t) / pace, exceeds
// kBudgetMargin budgets; a run that merely needs about its budget is left to
// the budget itself.
//
// One object per run (it is not shared); the caller feeds it the elapsed
// compute time and the simulated time reached.
class RunPaceWatch {
 public:
  static constexpr double kGraceWall_s = 2.0;
  static constexpr double kBudgetMargin = 2.0;

  RunPaceWatch(double duration_s, double wall_time_budget_s)
      : duration_s_(duration_s), budget_s_(wall_time_budget_s) {}

  // After `wall_s` seconds of computing the run has reached simulated time
  // `t_s`: true if it is hopeless (see above). Calls must come with
  // non-decreasing wall_s.
  bool hopeless(double wall_s, double t_s);

  // Why the last call returned true, e.g. "after 3 s of computing the run
  // reached t = 1.2e-06 s of 1 s; at this pace it needs ~700 h, beyond the
  // wall-time budget of 1 h".
  std::string explanation() const;

 private:
  struct Mark {
    double wall_s = 0.0, t_s = 0.0;
  };
  double duration_s_, budget_s_;
  Mark window_start_, last_mark_;   // the pace is measured from window_start_
  double next_mark_wall_s_ = 1.0;
  double wall_s_ = 0.0, t_s_ = 0.0, projected_wall_s_ = 0.0;
};

// "45 s", "12 min", "700 h": a wall time in the unit a person reads best.
std::string wall_time_text(double seconds);

struct SimulationObserver {
  // Called now and then with the simulated time (progress on long runs).
  std::function<void(double t_s)> progress;
  // Read at every step when set: once true, simulate() throws SimulationStopped
  // (a signal's request to stop, InterruptGuard's flag, ends a long run at once).
  const std::atomic<bool>* stop = nullptr;
};

// A run abandoned because its observer's stop flag was raised: neither a
// result nor a failure. t_s is the simulated time it had reached.
class SimulationStopped : public std::runtime_error {
 public:
  SimulationStopped(double t_s, double duration_s);
  double t_s;
};

// (f, c_q, M0) come from `inputs`; its set-points are replaced by those of
// the scenario (model_inputs_for) and, in time, by its drive schedule.
Trajectory simulate(const RoverModel& model, const Scenario& scenario,
                    const ModelInputs& inputs, const SimulationObserver& observer = {});

// Empty if a wheel carried load at some sample of a finished run; otherwise
// why the run says nothing of the contacts or the S-structure's compression
// ("no wheel touched the ground: within the run's 0.05 s, ...", a note of
// core/run_note.hpp). A drop from
// too high (a height in millimetres), too little gravity or too short a run
// does that.
std::string no_wheel_touched_note(const Trajectory& tr);

// Empty unless the chassis origin G went below `terrain` at some sample of
// a finished run; otherwise a note (core/run_note.hpp) with the deepest
// point and its time: the wheels gave way under an impact beyond what the
// contact model holds (a drop from metres, a landing at metres per second),
// and the run is not physical even if it rebounds.
std::string chassis_through_ground_note(const Trajectory& tr, const Terrain& terrain);

}  // namespace rover
