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
    report.detail = "step " + number_text(h) + " s is below " + number_text(StallWatch::kRoundingUnits) +
                    " rounding units of the time (" + number_text(floor) + " s)";
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

// Contacts per wheel at the last right-hand side of `workspace`: the regions
// and, of them, the ones that push. The normal force jumps where a region
// begins to push (F_n = max(0, k p^sigma + c dp/dt) with dp/dt > 0 at p = 0),
// so a step whose two ends differ here has a force discontinuity inside.
using ContactSignature = std::array<int, 2 * kNumLegs>;

ContactSignature contact_signature(const DynamicsWorkspace& workspace) {
  ContactSignature s{};
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const WheelContacts& wheel = workspace.contacts[leg];
    s[2 * leg] = wheel.count;
    for (int k = 0; k < wheel.count; ++k) s[2 * leg + 1] += wheel.points[k].normal_force_N > 0.0 ? 1 : 0;
  }
  return s;
}

}  // namespace

// Dormand-Prince 5(4) with odeint's step control, driven step by step so that
// a rejected try can be inspected. A try that crosses a contact onset meets a
// jump of the acceleration: its error estimate is about h times the jump and
// falls below atol only at steps of atol / jump (1e-14 s for atol 1e-12), so
// the step size would shrink to underflow. Such a try, once it is at
// min_step and its two ends have different contact sets (the jump is located
// inside it), is accepted: its error is at most min_step times the jump in
// the speeds and min_step^2 times it in the positions, and it is counted in
// report.discontinuity_steps.
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
  ContactSignature contacts = contact_signature(workspace);
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
      if (contact_signature(workspace) == contacts) {
        report.status = SimulationStatus::kStepSizeUnderflow;
        report.failed_at_s = t0;
        report.detail = "step " + number_text(h) + " s is below min_step " + number_text(settings.min_step_s) +
                        " s with no contact onset inside the step";
        return report;
      }
      ++report.discontinuity_steps;  // accepted at min_step across the located jump
      t = t0 + h_tried;
      h = h_tried;
    }
    contacts = contact_signature(workspace);  // the last evaluation is at x_new (FSAL)
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
      bad = step_is_bad(report, stall, t_start + static_cast<double>(s + 1) * h, h, x, request);
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
