// Command-line options shared by several subcommands: overrides of the study
// inputs (f, c_q, the 8 preloads M0), and the help of --integrator.
#pragma once

#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "core/number_text.hpp"
#include "core/scenario.hpp"
#include "core/simulate.hpp"

namespace rover::cli {

struct InputOverrides {
  std::optional<double> f, c_q;
  std::string M0;  // comma-separated, 8 values
};

inline void add_input_overrides(CLI::App& app, InputOverrides& o) {
  app.add_option("--f", o.f, "S-structure sharpness f [1/rad] (default: the rover config)");
  app.add_option("--cq", o.c_q, "S-structure damping c_q [N m s/rad] (default: the rover config)");
  app.add_option("--M0", o.M0, "The 8 preloads M0 [N m], comma-separated, order 11,12,21,22,31,32,41,42");
}

// "dopri5 (rtol 1e-06, atol 1e-09), rk4 (step 1e-05 s), rosenbrock (...)": the
// methods --integrator takes, with the defaults default_integrator_settings()
// gives them, so the help cannot drift from the code.
inline std::string integrator_choices_text() {
  const IntegratorSettings dopri5 = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  const IntegratorSettings rk4 = default_integrator_settings(IntegratorMethod::kRungeKutta4);
  const IntegratorSettings rosenbrock = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  return "dopri5 (rtol " + number_text(dopri5.relative_tolerance) + ", atol " +
         number_text(dopri5.absolute_tolerance) + "), rk4 (step " + number_text(rk4.fixed_step_s) +
         " s), rosenbrock (stiff, rtol " + number_text(rosenbrock.relative_tolerance) + ", atol " +
         number_text(rosenbrock.absolute_tolerance) + ")";
}

inline ModelInputs apply_overrides(const InputOverrides& o, ModelInputs in) {
  if (o.f) {
    if (!(*o.f > 0.0)) throw std::invalid_argument("--f must be positive, got " + std::to_string(*o.f));
    in.sharpness_f = *o.f;
  }
  if (o.c_q) {
    if (!(*o.c_q >= 0.0)) throw std::invalid_argument("--cq must not be negative, got " + std::to_string(*o.c_q));
    in.damping_c_q = *o.c_q;
  }
  if (!o.M0.empty()) {
    std::stringstream ss(o.M0);
    std::string item;
    std::size_t n = 0;
    while (std::getline(ss, item, ',')) {
      if (n == in.preload_Nm.size())
        throw std::invalid_argument("--M0 takes 8 values, got more: '" + o.M0 + "'");
      try {
        in.preload_Nm[n++] = std::stod(item);
      } catch (const std::exception&) {
        throw std::invalid_argument("--M0: '" + item + "' is not a number");
      }
    }
    if (n != in.preload_Nm.size())
      throw std::invalid_argument("--M0 takes 8 values, got " + std::to_string(n));
  }
  return in;
}

}  // namespace rover::cli
