#include "core/scenario.hpp"

#include <cmath>
#include <stdexcept>

#include "core/integrators.hpp"
#include "core/number_text.hpp"

namespace rover {

const char* integrator_name(IntegratorMethod method) {
  switch (method) {
    case IntegratorMethod::kDormandPrince45: return "dopri5";
    case IntegratorMethod::kRungeKutta4: return "rk4";
    case IntegratorMethod::kRosenbrockW: return "rosenbrock";
    case IntegratorMethod::kRodas4: return "rodas4";
  }
  return "unknown";
}

IntegratorMethod integrator_from_name(const std::string& name) {
  if (name == "dopri5" || name == "rk45") return IntegratorMethod::kDormandPrince45;
  if (name == "rk4") return IntegratorMethod::kRungeKutta4;
  if (name == "rosenbrock" || name == "ros34pw2") return IntegratorMethod::kRosenbrockW;
  if (name == "rodas4") return IntegratorMethod::kRodas4;
  throw std::invalid_argument("unknown integrator '" + name + "' (known: dopri5, rk4, rosenbrock, rodas4)");
}

IntegratorSettings default_integrator_settings(IntegratorMethod method) {
  IntegratorSettings s;
  s.method = method;
  if (method == IntegratorMethod::kRosenbrockW || method == IntegratorMethod::kRodas4) {
    s.relative_tolerance = 1e-5;
    s.absolute_tolerance = 2e-4;
  }
  return s;
}

namespace {

bool fail(std::string* why, const std::string& message) {
  if (why != nullptr) *why = message;
  return false;
}

bool positive_finite(double v) { return v > 0.0 && std::isfinite(v); }

}  // namespace

bool IntegratorSettings::IsValid(std::string* why) const {
  const std::string method_name = integrator_name(method);
  if (method == IntegratorMethod::kRungeKutta4) {
    if (!positive_finite(fixed_step_s))
      return fail(why, "rk4: fixed_step must be finite and > 0, got " + number_text(fixed_step_s) + " s");
    return true;
  }
  if (!positive_finite(relative_tolerance))
    return fail(why, method_name + ": rtol must be finite and > 0, got " + number_text(relative_tolerance));
  if (!positive_finite(absolute_tolerance))
    return fail(why, method_name + ": atol must be finite and > 0, got " + number_text(absolute_tolerance));
  if (!(relative_tolerance >= kMinRelativeTolerance && relative_tolerance <= kMaxRelativeTolerance))
    return fail(why, method_name + ": rtol must lie in [" + number_text(kMinRelativeTolerance) + ", " +
                         number_text(kMaxRelativeTolerance) + "], got " + number_text(relative_tolerance));
  if (!(absolute_tolerance >= kMinAbsoluteTolerance && absolute_tolerance <= kMaxAbsoluteTolerance))
    return fail(why, method_name + ": atol must lie in [" + number_text(kMinAbsoluteTolerance) + ", " +
                         number_text(kMaxAbsoluteTolerance) + "] m (below, less than round-off), got " +
                         number_text(absolute_tolerance));
  const bool stiff = method == IntegratorMethod::kRosenbrockW || method == IntegratorMethod::kRodas4;
  if (stiff && !(slip_tolerance > 0.0 && slip_tolerance <= kMaxSlipTolerance))
    return fail(why, method_name + ": slip_tol must lie in (0, " + number_text(kMaxSlipTolerance) + "], got " +
                         number_text(slip_tolerance));
  if (!positive_finite(min_step_s) || !positive_finite(initial_step_s) || !positive_finite(max_step_s))
    return fail(why, method_name + ": min_step, initial_step and max_step must be finite and > 0, got " +
                         number_text(min_step_s) + ", " + number_text(initial_step_s) + ", " +
                         number_text(max_step_s) + " s");
  if (!(min_step_s <= initial_step_s && initial_step_s <= max_step_s))
    return fail(why, method_name + ": need min_step <= initial_step <= max_step, got " +
                         number_text(min_step_s) + " <= " + number_text(initial_step_s) + " <= " +
                         number_text(max_step_s) + " s");
  return true;
}

bool scenario_is_valid(const Scenario& scenario, std::string* why) {
  if (!positive_finite(scenario.duration_s))
    return fail(why, "duration must be finite and > 0, got " + number_text(scenario.duration_s) + " s");
  if (!positive_finite(scenario.output_rate_hz))
    return fail(why, "output rate must be finite and > 0, got " + number_text(scenario.output_rate_hz) + " Hz");
  if (!(scenario.wall_time_budget_s >= 0.0) || std::isnan(scenario.wall_time_budget_s))
    return fail(why, "wall-time budget must be >= 0, got " + number_text(scenario.wall_time_budget_s) + " s");
  if (!scenario.integrator.IsValid(why)) return false;
  if (scenario.integrator.method == IntegratorMethod::kRungeKutta4) {
    const double period = 1.0 / scenario.output_rate_hz;
    const double steps = period / scenario.integrator.fixed_step_s;
    if (steps < 1.0 - 1e-9 || std::abs(steps - std::round(steps)) > 1e-9 * steps)
      return fail(why, "rk4: fixed_step " + number_text(scenario.integrator.fixed_step_s) +
                           " s does not divide the output period " + number_text(period) +
                           " s (use the period divided by a whole number)");
    // The stall watch ends any run slower than this pace as collapsed.
    const double max_steps = static_cast<double>(StallWatch::kWindowSteps) / StallWatch::kWindowFraction;
    if (const double run_steps = scenario.duration_s / scenario.integrator.fixed_step_s; run_steps > max_steps) {
      // The smallest step that both divides the output period and stays within max_steps.
      const double divisions = std::max(1.0, std::floor(period / (scenario.duration_s / max_steps)));
      return fail(why, "rk4: fixed_step " + number_text(scenario.integrator.fixed_step_s) + " s takes " +
                           number_text(run_steps) + " steps over the duration " + number_text(scenario.duration_s) +
                           " s, more than the " + number_text(max_steps) + " a run may take; use at least " +
                           number_text(period / divisions) + " s (the output period " + number_text(period) +
                           " s divided by " + number_text(divisions) + ")");
    }
  }
  return true;
}

std::size_t output_sample_count(const Scenario& scenario) {
  const double period = 1.0 / scenario.output_rate_hz;
  return static_cast<std::size_t>(std::floor(scenario.duration_s / period * (1.0 + 1e-12))) + 1;
}

}  // namespace rover
