// The accuracy-to-integrator map of accuracy_choice.hpp: a table of measured
// frontier points (docs/model.md §9), cheapest first.
#include "core/accuracy_choice.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "core/number_text.hpp"

namespace rover {
namespace {

// One setting of the frontier and the worst RMS difference of B_l z and
// B_r z from the reference that it gave.
struct FrontierPoint {
  IntegratorMethod method;
  double relative_tolerance, absolute_tolerance;
  double slip_tolerance;  // 0: the method's default (rosenbrock, rodas4); dopri5 has none
  double worst_rms_error_m;
};

// The non-dominated settings of bench/accuracy_cost.sh (AMD EPYC, 2 cores),
// cheapest first: worst RMS over the five paper scenarios (both drops, the
// obstacle at 0.34, 1 and 2 m/s) against Dormand-Prince at rtol 1e-10, with
// the right-hand sides the five runs took together in the comment. Below
// the default, a tighter slip tolerance buys more than a tighter atol alone:
// ROS34PW2 at atol 1e-5, 1e-6 and 1e-7 with the default slip tolerance
// (0.011 mm, 50 k; 0.0044 mm, 89 k; 4.7e-4 mm, 156 k) is beaten, as is every
// RODAS4 setting measured (atol 2e-4: 0.017 mm, 58 k; atol 1e-5: 0.0013 mm,
// 107 k; rtol 1e-6: 1.5e-4 mm, 461 k; rtol 1e-7: 5.2e-5 mm, 1.2 M).
constexpr std::array<FrontierPoint, 14> kMeasuredFrontier = {{
    {IntegratorMethod::kRosenbrockW, 1e-4, 2e-3, 0.0, 1.29e-4},        //  26 k
    {IntegratorMethod::kRosenbrockW, 1e-5, 2e-4, 0.0, 1.7e-5},         //  30 k, the stiff default
    {IntegratorMethod::kRosenbrockW, 1e-5, 1e-5, 0.01, 2.01e-6},       //  56 k
    {IntegratorMethod::kRosenbrockW, 1e-5, 1e-5, 0.005, 1.26e-6},      //  60 k
    {IntegratorMethod::kRosenbrockW, 1e-5, 3e-6, 0.01, 9.3e-7},        //  71 k
    {IntegratorMethod::kRosenbrockW, 1e-5, 1e-6, 0.01, 3.5e-7},        //  91 k
    {IntegratorMethod::kRosenbrockW, 1e-5, 3e-7, 0.01, 3.25e-7},       // 121 k
    {IntegratorMethod::kRosenbrockW, 1e-5, 1e-7, 0.002, 1.44e-7},      // 159 k
    {IntegratorMethod::kRosenbrockW, 1e-5, 1e-8, 0.0, 8.1e-8},         // 267 k
    {IntegratorMethod::kRosenbrockW, 1e-6, 1e-8, 0.0, 2.8e-8},         // 313 k
    {IntegratorMethod::kDormandPrince45, 1e-6, 1e-9, 0.0, 1.3e-9},     // 3.0 M
    {IntegratorMethod::kDormandPrince45, 1e-7, 1e-10, 0.0, 2.74e-10},  // 3.1 M
    {IntegratorMethod::kDormandPrince45, 1e-8, 1e-11, 0.0, 4.9e-11},   // 3.3 M
    {IntegratorMethod::kDormandPrince45, 1e-9, 1e-12, 0.0, 3.74e-12},  // 3.8 M
}};

IntegratorSettings settings_of(const FrontierPoint& p) {
  IntegratorSettings s = default_integrator_settings(p.method);
  s.relative_tolerance = p.relative_tolerance;
  s.absolute_tolerance = p.absolute_tolerance;
  if (p.slip_tolerance > 0.0) s.slip_tolerance = p.slip_tolerance;
  return s;
}

IntegratorChoice choice_of(const FrontierPoint& p) {
  IntegratorChoice c;
  c.settings = settings_of(p);
  c.measured_error_m = p.worst_rms_error_m;
  c.description = std::string(integrator_name(p.method)) + " rtol " + number_text(p.relative_tolerance) +
                  " atol " + number_text(p.absolute_tolerance);
  if (p.slip_tolerance > 0.0) c.description += " slip_tol " + number_text(p.slip_tolerance);
  return c;
}

}  // namespace

IntegratorChoice integrator_for_accuracy(double accuracy_m) {
  if (!(accuracy_m > kMostAccuracy_m && accuracy_m < kLeastAccuracy_m))
    throw std::invalid_argument("accuracy " + number_text(accuracy_m) + " m is outside (" +
                                number_text(kMostAccuracy_m) + ", " + number_text(kLeastAccuracy_m) + ") m");
  for (const FrontierPoint& p : kMeasuredFrontier)
    if (p.worst_rms_error_m <= accuracy_m) return choice_of(p);
  IntegratorChoice most = choice_of(kMeasuredFrontier.back());
  most.description += " (the most accurate measured setting, " + number_text(most.measured_error_m) +
                      " m; " + number_text(accuracy_m) + " m asked)";
  return most;
}

std::optional<double> expected_error_m(const IntegratorSettings& settings) {
  std::optional<double> error_m;
  for (const FrontierPoint& p : kMeasuredFrontier) {
    const IntegratorSettings measured = settings_of(p);
    if (p.method == settings.method && settings.relative_tolerance <= measured.relative_tolerance &&
        settings.absolute_tolerance <= measured.absolute_tolerance &&
        settings.slip_tolerance <= measured.slip_tolerance)
      error_m = std::min(error_m.value_or(p.worst_rms_error_m), p.worst_rms_error_m);
  }
  return error_m;
}

}  // namespace rover
