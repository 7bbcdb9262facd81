// Explicit integrators with Boost.Odeint: Dormand-Prince 5(4) with step control
// and dense output, and fixed-step classic RK4 (see integrators.hpp).
// Step control: err = max_i |e_i| / (atol + rtol |x_i|), as MATLAB's and
// SciPy's RK45 (odeint's derivative term is switched off).
#include "core/integrators.hpp"

#include <array>
#include <cmath>
#include <limits>

// Odeint's steppers copy state buffers before their first use; GCC 12 warns
// about that inside the library (-Wmaybe-uninitialized), not about our code.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/external/eigen/eigen.hpp>
#pragma GCC diagnostic pop

#include "core/equations_of_motion.hpp"
#include "core/number_text.hpp"

namespace rover {
namespace odeint = boost::numeric::odeint;

ModelInputs OdeSystem::inputs_at(double t) const {
  if (drive_schedule == nullptr) return inputs;
  ModelInputs in = inputs;
  const WheelCommands w = drive_schedule->at(t);
  in.steer_ref_rad = w.steer_rad;
  in.wheel_speed_ref_radps = w.wheel_speed_radps;
  return in;
}

StateVector ode_derivative(const OdeSystem& system, DynamicsWorkspace& workspace, double t,
                           const StateVector& x) {
  if (system.drive_schedule == nullptr) return state_derivative_articulated(system.model, workspace, system.inputs, x);
  return state_derivative_articulated(system.model, workspace, system.inputs_at(t), x);
}

const char* status_name(SimulationStatus status) {
  switch (status) {
    case SimulationStatus::kOk: return "ok";
    case SimulationStatus::kNonFinite: return "non-finite state";
    case SimulationStatus::kStepSizeUnderflow: return "step size underflow";
    case SimulationStatus::kTimeBudgetExceeded: return "time budget exceeded";
    case SimulationStatus::kInvalidScenario: return "invalid scenario";
    case SimulationStatus::kStepSizeCollapsed: return "step size collapsed";
  }
  return "unknown";
}

namespace {

double sample_time(const IntegrationRequest& r, std::size_t k) {
  return static_cast<double>(k) * r.sample_period_s;
}

}  // namespace

bool step_is_bad(IntegrationReport& report, StallWatch& stall, double t, double h,
                 const StateVector& x, const IntegrationRequest& request) {
  ++report.steps;
  report.min_step_s = report.steps == 1 ? h : std::min(report.min_step_s, h);
  report.max_step_s = std::max(report.max_step_s, h);
  if (!x.allFinite()) {
    report.status = SimulationStatus::kNonFinite;
    report.failed_at_s = t;
    report.detail = "the state has NaN or infinite entries";
    return true;
  }
  const double duration = sample_time(request, request.sample_count - 1);
  const double floor = StallWatch::kRoundingUnits * std::numeric_limits<double>::epsilon() *
                       std::max(std::abs(t), duration);
  if (h < floor && t < duration) {  // the last step may end just past a sample
    report.status = SimulationStatus::kStepSizeCollapsed;
    report.failed_at_s = t;
    // The times of a run are resolved to the rounding of its longest one.
    const bool duration_sets_floor = duration > std::abs(t);
    report.detail = "step " + number_text(h) + " s is below " + number_text(StallWatch::kRoundingUnits) +
                    " rounding units of the " +
                    (duration_sets_floor ? "duration " + number_text(duration) + " s (" + number_text(floor) +
                                               " s), the finest step a run this long resolves in double precision"
                                         : "time (" + number_text(floor) + " s)");
    return true;
  }
  if (report.steps - stall.window_start_step >= StallWatch::kWindowSteps) {
    const double advanced = t - stall.window_start_t_s;
    if (advanced < StallWatch::kWindowFraction * duration) {
      report.status = SimulationStatus::kStepSizeCollapsed;
      report.failed_at_s = t;
      report.detail = "the last " + std::to_string(report.steps - stall.window_start_step) +
                      " steps advanced the time by " + number_text(advanced) + " s, less than " +
                      number_text(StallWatch::kWindowFraction) + " of the duration " +
                      number_text(duration) + " s";
      return true;
    }
    stall.window_start_step = report.steps;
    stall.window_start_t_s = t;
  }
  if (request.out_of_time && request.out_of_time()) {
    report.status = SimulationStatus::kTimeBudgetExceeded;
    report.failed_at_s = t;
    report.detail = "wall-time budget used up";
    return true;
  }
  return false;
}

namespace {

// The contacts of the last right-hand side of `workspace`, as far as they
// make the right-hand side jump: per wheel the regions, the ones that push,
// and their terrain normals. The normal force jumps where a region begins to
// push (F_n = max(0, k p^sigma + c dp/dt), dp/dt > 0 at p = 0), and the
// contact force turns at once where the contact point crosses a kink of the
// terrain (a grid line where the bilinear slope jumps: the foot and the top
// of a ramp).
struct ContactSet {
  std::array<int, kNumLegs> regions{}, pushing{};
  std::array<std::array<Vec3, kMaxContactsPerWheel>, kNumLegs> normals{};
};

ContactSet contact_set(const DynamicsWorkspace& workspace) {
  ContactSet s;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const WheelContacts& wheel = workspace.contacts[leg];
    s.regions[leg] = wheel.count;
    for (int k = 0; k < wheel.count; ++k) {
      s.pushing[leg] += wheel.points[k].normal_force_N > 0.0 ? 1 : 0;
      s.normals[leg][k] = wheel.points[k].normal;
    }
  }
  return s;
}

// Whether the right-hand side jumps between two contact sets a step of
// min_step apart: a contact begins or ends, or a normal turns by more than
// kKinkTurn_rad, which a smooth terrain cannot do within such a step (a
// contact point moving at 10 m/s over a 1 cm radius of curvature turns its
// normal by 1e-9 rad in 1e-12 s; a grid line of the ramp turns it by 0.17).
constexpr double kKinkTurn_rad = 1e-6;

bool contact_forces_jump(const ContactSet& a, const ContactSet& b) {
  if (a.regions != b.regions || a.pushing != b.pushing) return true;
  for (int leg = 0; leg < kNumLegs; ++leg)
    for (int k = 0; k < a.regions[leg]; ++k)
      if ((a.normals[leg][k] - b.normals[leg][k]).norm() > kKinkTurn_rad) return true;
  return false;
}

}  // namespace

// Dormand-Prince 5(4) with odeint's step control, driven step by step so that
// a rejected try can be inspected. A try across a jump of the right-hand side
// (contact_forces_jump()) has an error estimate of about h times the jump,
// below atol only at steps of atol / jump (1e-14 s for atol 1e-12), so the
// step size would shrink to underflow. Such a try, once it is at min_step
// and its two ends show the jump (located inside it), is accepted: its error
// is at most min_step times the jump in the speeds and min_step^2 times it in
// the positions. These steps are counted in report.discontinuity_steps. A try
// at min_step that fails without a jump is an underflow, as before.
IntegrationReport integrate_dormand_prince(const OdeSystem& system, StateVector x,
                                           const IntegratorSettings& settings,
                                           const IntegrationRequest& request) {
  using Stepper = odeint::runge_kutta_dopri5<StateVector, double, StateVector, double,
                                             odeint::vector_space_algebra>;
  using Checker = odeint::default_error_checker<double, odeint::vector_space_algebra,
                                                odeint::default_operations>;
  using Adjuster = odeint::default_step_adjuster<double, double>;
  using Controlled = odeint::controlled_runge_kutta<Stepper, Checker, Adjuster>;

  IntegrationReport report;
  StallWatch stall;
  request.record(0.0, x);
  if (request.sample_count < 2) return report;
  DynamicsWorkspace workspace;
  auto rhs = [&](const StateVector& s, StateVector& ds, double t) {
    ++report.rhs_evaluations;
    ds = ode_derivative(system, workspace, t, s);
  };
  Controlled stepper(Checker(settings.absolute_tolerance, settings.relative_tolerance, 1.0, 0.0),
                     Adjuster(settings.max_step_s));
  StateVector dx, x_new, dx_new, sample;
  rhs(x, dx, 0.0);
  ContactSet contacts = contact_set(workspace);
  double t = 0.0, h = settings.initial_step_s;
  std::size_t next = 1;
  while (next < request.sample_count) {
    const double t0 = t, h_tried = h;
    if (stepper.try_step(rhs, x, dx, t, x_new, dx_new, h) == odeint::fail) {
      ++report.rejected_steps;
      if (h >= settings.min_step_s) continue;
      if (h_tried > settings.min_step_s) {  // one last try at min_step itself
        h = settings.min_step_s;
        continue;
      }
      if (!contact_forces_jump(contact_set(workspace), contacts)) {
        report.status = SimulationStatus::kStepSizeUnderflow;
        report.failed_at_s = t0;
        report.detail = "step " + number_text(h) + " s is below min_step " + number_text(settings.min_step_s) +
                        " s with no contact jump inside the step";
        return report;
      }
      ++report.discontinuity_steps;  // accepted at min_step across the located jump
      t = t0 + h_tried;
      h = h_tried;
    }
    contacts = contact_set(workspace);  // the last evaluation is at x_new (FSAL)
    if (step_is_bad(report, stall, t, t - t0, x_new, request)) break;
    while (next < request.sample_count && sample_time(request, next) <= t) {
      stepper.stepper().calc_state(sample_time(request, next), sample, x, dx, t0, x_new, dx_new, t);
      request.record(sample_time(request, next), sample);
      ++next;
    }
    x.swap(x_new);
    dx.swap(dx_new);
    if (request.progress) request.progress(t);
  }
  return report;
}

IntegrationReport integrate_rk4(const OdeSystem& system, StateVector x,
                                const IntegratorSettings& settings, const IntegrationRequest& request) {
  odeint::runge_kutta4<StateVector, double, StateVector, double, odeint::vector_space_algebra> stepper;
  IntegrationReport report;
  StallWatch stall;
  DynamicsWorkspace workspace;
  auto rhs = [&](const StateVector& s, StateVector& ds, double t) {
    ++report.rhs_evaluations;
    ds = ode_derivative(system, workspace, t, s);
  };
  // Sub-steps of equal length that divide the sample period (the step
  // divides it to 1e-9 relative: scenario_is_valid(); a step at the round-off
  // of the time is stopped by step_is_bad()).
  const long long substeps =
      std::max(1LL, std::llround(request.sample_period_s / settings.fixed_step_s));
  const double h = request.sample_period_s / static_cast<double>(substeps);
  request.record(0.0, x);
  for (std::size_t k = 1; k < request.sample_count; ++k) {
    const double t_start = sample_time(request, k - 1);
    bool bad = false;
    for (long long s = 0; s < substeps && !bad; ++s) {
      stepper.do_step(rhs, x, t_start + static_cast<double>(s) * h, h);
      const double t = t_start + static_cast<double>(s + 1) * h;
      bad = step_is_bad(report, stall, t, h, x, request);
      // Between samples too: the wall-time watch measures the pace by it.
      if (!bad && s + 1 < substeps && request.progress) request.progress(t);
    }
    if (bad) break;
    request.record(sample_time(request, k), x);
    if (request.progress) request.progress(sample_time(request, k));
  }
  return report;
}

IntegrationReport integrate(const OdeSystem& system, const StateVector& x0,
                            const IntegratorSettings& settings, const IntegrationRequest& request) {
  switch (settings.method) {
    case IntegratorMethod::kDormandPrince45:
      return integrate_dormand_prince(system, x0, settings, request);
    case IntegratorMethod::kRungeKutta4:
      return integrate_rk4(system, x0, settings, request);
    case IntegratorMethod::kRosenbrockW:
    case IntegratorMethod::kRodas4:
      return integrate_rosenbrock(system, x0, settings, request);
  }
  return {};
}

}  // namespace rover
