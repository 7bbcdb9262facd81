// Explicit integrators with Boost.Odeint: Dormand-Prince 5(4) with step control
// and dense output, and fixed-step classic RK4 (see integrators.hpp).
// Step control: err = max_i |e_i| / (atol + rtol |x_i|), as MATLAB's and
// SciPy's RK45 (odeint's derivative term is switched off).
#include "core/integrators.hpp"

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
  if (system.drive_schedule == nullptr) return state_derivative(system.model, workspace, system.inputs, x);
  return state_derivative(system.model, workspace, system.inputs_at(t), x);
}

const char* status_name(SimulationStatus status) {
  switch (status) {
    case SimulationStatus::kOk: return "ok";
    case SimulationStatus::kNonFinite: return "non-finite state";
    case SimulationStatus::kStepSizeUnderflow: return "step size underflow";
    case SimulationStatus::kTimeBudgetExceeded: return "time budget exceeded";
    case SimulationStatus::kInvalidScenario: return "invalid scenario";
  }
  return "unknown";
}

namespace {

double sample_time(const IntegrationRequest& r, std::size_t k) {
  return static_cast<double>(k) * r.sample_period_s;
}

}  // namespace

bool step_is_bad(IntegrationReport& report, double t, double h, const StateVector& x,
                 const IntegrationRequest& request) {
  ++report.steps;
  report.min_step_s = report.steps == 1 ? h : std::min(report.min_step_s, h);
  report.max_step_s = std::max(report.max_step_s, h);
  if (!x.allFinite()) {
    report.status = SimulationStatus::kNonFinite;
    report.failed_at_s = t;
    report.detail = "the state has NaN or infinite entries";
    return true;
  }
  if (request.out_of_time && request.out_of_time()) {
    report.status = SimulationStatus::kTimeBudgetExceeded;
    report.failed_at_s = t;
    report.detail = "wall-time budget used up";
    return true;
  }
  return false;
}

IntegrationReport integrate_dormand_prince(const OdeSystem& system, StateVector x,
                                           const IntegratorSettings& settings,
                                           const IntegrationRequest& request) {
  using Stepper = odeint::runge_kutta_dopri5<StateVector, double, StateVector, double,
                                             odeint::vector_space_algebra>;
  using Checker = odeint::default_error_checker<double, odeint::vector_space_algebra,
                                                odeint::default_operations>;
  using Adjuster = odeint::default_step_adjuster<double, double>;
  using Controlled = odeint::controlled_runge_kutta<Stepper, Checker, Adjuster>;
  using Dense = odeint::dense_output_runge_kutta<Controlled>;

  IntegrationReport report;
  request.record(0.0, x);
  if (request.sample_count < 2) return report;
  DynamicsWorkspace workspace;
  auto rhs = [&](const StateVector& s, StateVector& ds, double t) {
    ++report.rhs_evaluations;
    ds = ode_derivative(system, workspace, t, s);
  };
  Dense stepper(Controlled(Checker(settings.absolute_tolerance, settings.relative_tolerance, 1.0, 0.0),
                           Adjuster(settings.max_step_s)));
  stepper.initialize(x, 0.0, settings.initial_step_s);
  StateVector sample;
  std::size_t next = 1;
  try {
    while (next < request.sample_count) {
      const auto [t0, t1] = stepper.do_step(rhs);
      if (step_is_bad(report, t1, t1 - t0, stepper.current_state(), request)) break;
      while (next < request.sample_count && sample_time(request, next) <= t1) {
        stepper.calc_state(sample_time(request, next), sample);
        request.record(sample_time(request, next), sample);
        ++next;
      }
      if (next < request.sample_count && stepper.current_time_step() < settings.min_step_s) {
        report.status = SimulationStatus::kStepSizeUnderflow;
        report.failed_at_s = t1;
        report.detail = "step " + std::to_string(stepper.current_time_step()) +
                        " s is below min_step " + std::to_string(settings.min_step_s) + " s";
        break;
      }
      if (request.progress) request.progress(t1);
    }
  } catch (const odeint::step_adjustment_error& e) {
    report.status = SimulationStatus::kStepSizeUnderflow;
    report.failed_at_s = stepper.current_time();
    report.detail = e.what();
  }
  return report;
}

IntegrationReport integrate_rk4(const OdeSystem& system, StateVector x,
                                const IntegratorSettings& settings, const IntegrationRequest& request) {
  odeint::runge_kutta4<StateVector, double, StateVector, double, odeint::vector_space_algebra> stepper;
  IntegrationReport report;
  DynamicsWorkspace workspace;
  auto rhs = [&](const StateVector& s, StateVector& ds, double t) {
    ++report.rhs_evaluations;
    ds = ode_derivative(system, workspace, t, s);
  };
  // Sub-steps of equal length that divide the sample period.
  const int substeps = std::max(
      1, static_cast<int>(std::ceil(request.sample_period_s / settings.fixed_step_s - 1e-9)));
  const double h = request.sample_period_s / substeps;
  request.record(0.0, x);
  for (std::size_t k = 1; k < request.sample_count; ++k) {
    const double t_start = sample_time(request, k - 1);
    bool bad = false;
    for (int s = 0; s < substeps && !bad; ++s) {
      stepper.do_step(rhs, x, t_start + s * h, h);
      bad = step_is_bad(report, t_start + (s + 1) * h, h, x, request);
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
      return integrate_rosenbrock(system, x0, settings, request);
  }
  return {};
}

}  // namespace rover
