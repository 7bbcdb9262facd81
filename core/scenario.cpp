#include "core/scenario.hpp"

#include <cmath>
#include <stdexcept>

namespace rover {

const char* integrator_name(IntegratorMethod method) {
  switch (method) {
    case IntegratorMethod::kDormandPrince45: return "dopri5";
    case IntegratorMethod::kRungeKutta4: return "rk4";
    case IntegratorMethod::kRosenbrockW: return "rosenbrock";
  }
  return "unknown";
}

IntegratorMethod integrator_from_name(const std::string& name) {
  if (name == "dopri5" || name == "rk45") return IntegratorMethod::kDormandPrince45;
  if (name == "rk4") return IntegratorMethod::kRungeKutta4;
  if (name == "rosenbrock" || name == "ros34pw2") return IntegratorMethod::kRosenbrockW;
  throw std::invalid_argument("unknown integrator '" + name + "' (known: dopri5, rk4, rosenbrock)");
}

IntegratorSettings default_integrator_settings(IntegratorMethod method) {
  IntegratorSettings s;
  s.method = method;
  if (method == IntegratorMethod::kRosenbrockW) {
    s.relative_tolerance = 1e-5;
    s.absolute_tolerance = 2e-4;
  }
  return s;
}

std::size_t output_sample_count(const Scenario& scenario) {
  const double period = 1.0 / scenario.output_rate_hz;
  return static_cast<std::size_t>(std::floor(scenario.duration_s / period * (1.0 + 1e-12))) + 1;
}

}  // namespace rover
