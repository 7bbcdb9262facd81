#include "core/scenario.hpp"

#include <stdexcept>

namespace rover {

const char* integrator_name(IntegratorMethod method) {
  switch (method) {
    case IntegratorMethod::kDormandPrince45: return "dopri5";
    case IntegratorMethod::kRungeKutta4: return "rk4";
  }
  return "unknown";
}

IntegratorMethod integrator_from_name(const std::string& name) {
  if (name == "dopri5" || name == "rk45") return IntegratorMethod::kDormandPrince45;
  if (name == "rk4") return IntegratorMethod::kRungeKutta4;
  throw std::invalid_argument("unknown integrator '" + name + "' (known: dopri5, rk4)");
}

}  // namespace rover
