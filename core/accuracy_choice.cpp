// The accuracy-to-integrator map of accuracy_choice.hpp: a table of measured
// frontier points (docs/model.md §9), cheapest first.
#include "core/accuracy_choice.hpp"

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
  double worst_rms_error_m;
};

// The non-dominated settings of bench/accuracy_cost.sh (AMD EPYC, 2 cores),
// cheapest first: worst RMS over the horizontal and skewed drops and the
// 2 m/s obstacle run against Dormand-Prince at rtol 1e-10, with the
// right-hand sides the three runs took together in the comment. Settings
// that a cheaper one matched or beat are left out: ROS34PW2 at rtol 1e-5,
// atol 1e-5 (0.027 mm, 32 k) and RODAS4 at atol 1e-6 (0.027 mm, 123 k), whose
// error does not fall with the tolerance because a brief contact of the
// obstacle run lands in a different step.
constexpr std::array<FrontierPoint, 11> kMeasuredFrontier = {{
    {IntegratorMethod::kRosenbrockW, 1e-4, 2e-3, 9.9e-5},        //  12 k
    {IntegratorMethod::kRosenbrockW, 1e-5, 2e-4, 2.0e-5},        //  17 k, the stiff default
    {IntegratorMethod::kRodas4, 1e-5, 2e-4, 8.5e-6},             //  34 k
    {IntegratorMethod::kRosenbrockW, 1e-5, 1e-6, 5.8e-6},        //  59 k
    {IntegratorMethod::kRodas4, 1e-5, 1e-5, 1.4e-6},             //  69 k
    {IntegratorMethod::kRosenbrockW, 1e-5, 1e-8, 4.0e-8},        // 169 k
    {IntegratorMethod::kRosenbrockW, 1e-6, 1e-8, 2.0e-8},        // 205 k
    {IntegratorMethod::kDormandPrince45, 1e-6, 1e-9, 1.6e-9},    // 639 k
    {IntegratorMethod::kDormandPrince45, 1e-7, 1e-10, 2.8e-10},  // 706 k
    {IntegratorMethod::kDormandPrince45, 1e-8, 1e-11, 4.7e-11},  // 1.0 M
    {IntegratorMethod::kDormandPrince45, 1e-9, 1e-12, 6.0e-12},  // 3.1 M
}};

IntegratorChoice choice_of(const FrontierPoint& p) {
  IntegratorChoice c;
  c.settings = default_integrator_settings(p.method);
  c.settings.relative_tolerance = p.relative_tolerance;
  c.settings.absolute_tolerance = p.absolute_tolerance;
  c.measured_error_m = p.worst_rms_error_m;
  c.description = std::string(integrator_name(p.method)) + " rtol " + number_text(p.relative_tolerance) +
                  " atol " + number_text(p.absolute_tolerance);
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

}  // namespace rover
