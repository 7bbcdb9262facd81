// simulate(): a scenario integrated with the chosen integrator, sampled at the
// output rate into the outputs of docs/model.md §8 (see simulate.hpp).
#include "core/simulate.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <optional>
#include <stdexcept>

#include "core/contact.hpp"
#include "core/integrators.hpp"
#include "core/number_text.hpp"
#include "core/run_note.hpp"

namespace rover {

ModelInputs model_inputs_for(const Scenario& scenario, const ModelInputs& inputs) {
  ModelInputs in = inputs;
  in.wheel_speed_ref_radps = scenario.wheel_speed_ref_radps;
  in.steer_ref_rad = scenario.steer_ref_rad;
  return in;
}

bool RunPaceWatch::hopeless(double wall_s, double t_s) {
  wall_s_ = wall_s;
  t_s_ = t_s;
  if (wall_s >= next_mark_wall_s_) {
    window_start_ = last_mark_;
    last_mark_ = {wall_s, t_s};
    while (next_mark_wall_s_ <= wall_s) next_mark_wall_s_ *= 2.0;
  }
  if (wall_s < kGraceWall_s || t_s >= duration_s_) return false;
  const double advanced_s = t_s - window_start_.t_s, window_wall_s = wall_s - window_start_.wall_s;
  projected_wall_s_ = advanced_s > 0.0 && window_wall_s > 0.0
                          ? wall_s + (duration_s_ - t_s) * window_wall_s / advanced_s
                          : std::numeric_limits<double>::infinity();
  return projected_wall_s_ > kBudgetMargin * budget_s_;
}

std::string RunPaceWatch::explanation() const {
  const std::string needs = std::isfinite(projected_wall_s_)
                                ? "at this pace it needs ~" + wall_time_text(projected_wall_s_)
                                : "it has not advanced for the last " +
                                      wall_time_text(wall_s_ - window_start_.wall_s);
  return "after " + wall_time_text(wall_s_) + " of computing the run reached t = " + number_text(t_s_) +
         " s of " + number_text(duration_s_) + " s; " + needs + ", beyond the wall-time budget of " +
         wall_time_text(budget_s_) + " (\"wall_time_budget\")";
}

std::string wall_time_text(double seconds) {
  char text[32];
  if (seconds < 120.0)
    std::snprintf(text, sizeof text, "%.3g s", seconds);
  else if (seconds < 3600.0)
    std::snprintf(text, sizeof text, "%.3g min", seconds / 60.0);
  else
    std::snprintf(text, sizeof text, "%.3g h", seconds / 3600.0);
  return text;
}

namespace {

using Clock = std::chrono::steady_clock;

// CPU time of the calling thread [s] (POSIX).
double thread_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

// Collects the outputs of docs/model.md §8 at the sample times.
class TrajectoryRecorder {
 public:
  TrajectoryRecorder(const RoverModel& model, std::size_t capacity, Trajectory& out)
      : model_(model), out_(out) {
    out_.t.reserve(capacity);
    q_rows_.reserve(capacity);
    u_rows_.reserve(capacity);
    fn_rows_.reserve(capacity);
  }

  void record(double t, const StateVector& x) {
    const Coordinates q = x.head<kNumCoordinates>(), u = x.tail<kNumCoordinates>();
    forward_pose_and_velocity(model_.tree, q, u, kin_);
    const TreeKinematics& kin = kin_;
    out_.t.push_back(t);
    q_rows_.push_back(q);
    u_rows_.push_back(u);
    out_.B_l_z.push_back(kin.nodes[node::bogie_left].origin.z());
    out_.B_r_z.push_back(kin.nodes[node::bogie_right].origin.z());
    out_.G_z.push_back(kin.nodes[node::chassis].origin.z());
    out_.pitch.push_back(q[coord::pitch]);
    out_.roll.push_back(q[coord::roll]);
    Eigen::Vector4d fn;
    for (int leg = 0; leg < kNumLegs; ++leg) {  // the contacts of stage 2 without their friction
      find_leg_wheel_contacts(model_.terrain, kin, leg, model_.parameters.geometry.wheel_radius_m, contacts_);
      compute_contact_normal_forces(kin, node::wheel(leg), model_.parameters.contact, contacts_);
      fn[leg] = contacts_.total_normal_force_N();
    }
    fn_rows_.push_back(fn);
  }

  void finish() {
    const auto n = static_cast<Eigen::Index>(q_rows_.size());
    out_.q.resize(n, kNumCoordinates);
    out_.u.resize(n, kNumCoordinates);
    out_.normal_force_N.resize(n, kNumLegs);
    for (Eigen::Index i = 0; i < n; ++i) {
      out_.q.row(i) = q_rows_[i].transpose();
      out_.u.row(i) = u_rows_[i].transpose();
      out_.normal_force_N.row(i) = fn_rows_[i].transpose();
    }
  }

 private:
  const RoverModel& model_;
  TreeKinematics kin_;     // at the sample being recorded
  WheelContacts contacts_;  // of one wheel there
  Trajectory& out_;
  std::vector<Coordinates> q_rows_, u_rows_;
  std::vector<Eigen::Vector4d> fn_rows_;
};

}  // namespace

Trajectory simulate(const RoverModel& model, const Scenario& scenario,
                    const ModelInputs& inputs, const SimulationObserver& observer) {
  const auto wall_start = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - wall_start).count(); };

  const ModelInputs model_inputs = model_inputs_for(scenario, inputs);

  Trajectory out;
  // A scenario that cannot run: no samples, the reason in the message.
  auto invalid = [&](const std::string& why) {
    out.status = SimulationStatus::kInvalidScenario;
    out.message = std::string(status_name(out.status)) + ": " + why;
    out.q.resize(0, kNumCoordinates);
    out.u.resize(0, kNumCoordinates);
    out.normal_force_N.resize(0, kNumLegs);
    out.wall_time_s = elapsed();
    return out;
  };
  if (std::string why; !scenario_is_valid(scenario, &why)) return invalid(why);

  // The drive schedule, compiled against this model's drive kinematics.
  std::optional<CompiledDriveSchedule> schedule;
  if (!scenario.drive.segments.empty()) {
    try {
      schedule.emplace(make_drive_kinematics(model.parameters), scenario.drive.segments,
                       scenario.drive.options);
    } catch (const std::invalid_argument& e) {
      return invalid(e.what());
    }
  }

  const double period = 1.0 / scenario.output_rate_hz;
  const std::size_t samples = output_sample_count(scenario);
  TrajectoryRecorder recorder(model, samples, out);

  IntegrationRequest request;
  request.sample_period_s = period;
  request.sample_count = samples;
  request.record = [&](double t, const StateVector& x) { recorder.record(t, x); };
  // The budget, and the pace that says it will be blown (RunPaceWatch; the
  // thread's CPU time is read every kPaceCheckSteps steps, a system call).
  constexpr long kPaceCheckSteps = 32;
  RunPaceWatch pace(static_cast<double>(samples - 1) * period, scenario.wall_time_budget_s);
  const double cpu_start_s = thread_cpu_seconds();
  double reached_s = 0.0;  // simulated time of the last accepted step
  long checks = 0;
  bool hopeless = false;
  request.out_of_time = [&] {
    if (elapsed() > scenario.wall_time_budget_s) return true;
    if (++checks % kPaceCheckSteps != 0) return false;
    hopeless = pace.hopeless(thread_cpu_seconds() - cpu_start_s, reached_s);
    return hopeless;
  };
  double last_progress_s = 0.0;
  request.progress = [&](double t) {
    reached_s = t;
    if (observer.stop != nullptr && observer.stop->load(std::memory_order_relaxed))
      throw SimulationStopped(t, scenario.duration_s);
    if (observer.progress && elapsed() - last_progress_s > 1.0) {
      last_progress_s = elapsed();
      observer.progress(t);
    }
  };

  const OdeSystem system{model, model_inputs, schedule ? &*schedule : nullptr};
  StateVector x0;
  x0 << scenario.initial_q, scenario.initial_u;
  const IntegrationReport report = integrate(system, x0, scenario.integrator, request);

  recorder.finish();
  out.status = report.status;
  if (!out.ok())
    out.message = std::string(status_name(out.status)) + " at t = " + number_text(report.failed_at_s) +
                  " s: " + (hopeless ? pace.explanation() : report.detail);
  out.rhs_evaluations = report.rhs_evaluations;
  out.steps = report.steps;
  out.rejected_steps = report.rejected_steps;
  out.discontinuity_steps = report.discontinuity_steps;
  out.min_step_s = report.min_step_s;
  out.max_step_s = report.max_step_s;
  out.wall_time_s = elapsed();
  return out;
}

SimulationStopped::SimulationStopped(double reached_s, double duration_s)
    : std::runtime_error("stopped on request at t = " + number_text(reached_s) + " of the run's " +
                         number_text(duration_s) + " s"),
      t_s(reached_s) {}

std::string no_wheel_touched_note(const Trajectory& tr) {
  if (!tr.ok() || tr.t.empty() || tr.normal_force_N.maxCoeff() > 0.0) return "";
  return run_note("no wheel touched the ground",
                  "within the run's " + number_text(tr.t.back()) + " s, B_l z went from " +
                      number_text(tr.B_l_z.front()) + " to " + number_text(tr.B_l_z.back()) +
                      " m (a drop height in millimetres, too little gravity or too short a run?)");
}

std::string chassis_through_ground_note(const Trajectory& tr, const Terrain& terrain) {
  if (!tr.ok()) return "";
  double deepest_m = 0.0;
  std::size_t at = 0;
  for (std::size_t k = 0; k < tr.t.size(); ++k) {
    const auto row = static_cast<Eigen::Index>(k);
    const double depth_m = terrain.height(tr.q(row, coord::x), tr.q(row, coord::y)) - tr.G_z[k];
    if (depth_m > deepest_m) {
      deepest_m = depth_m;
      at = k;
    }
  }
  if (!(deepest_m > 0.0)) return "";
  return run_note("the chassis went through the ground",
                  "its origin G reached " + number_text(deepest_m) + " m below the terrain at t = " +
                      number_text(tr.t[at]) + " s: the wheels gave way under an impact beyond the contact "
                      "model, and the run is not physical (a smaller drop height, a softer landing or a stiffer "
                      "k_g)");
}

}  // namespace rover
