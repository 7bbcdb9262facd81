// An integrator chosen by the accuracy asked of a run, in metres
// (docs/model.md §9): the cheapest setting of the measured accuracy-cost
// frontier (bench/accuracy_cost.sh: the five paper scenarios, the RMS
// difference of B_l z and B_r z from Dormand-Prince at rtol 1e-10) whose
// worst scenario is within the accuracy asked.
#pragma once

#include <optional>
#include <string>

#include "core/scenario.hpp"

namespace rover {

struct IntegratorChoice {
  IntegratorSettings settings;      // method, rtol, atol, slip_tol; the other fields at their defaults
  double measured_error_m = 0.0;    // worst RMS difference of the setting over the paper scenarios
  std::string description;          // e.g. "rosenbrock rtol 1e-05 atol 1e-05 slip_tol 0.01"
                                    // ("(the most accurate measured ...)" appended if short)
};

// The open interval of accuracies [m] the frontier answers for.
inline constexpr double kLeastAccuracy_m = 1e-2;
inline constexpr double kMostAccuracy_m = 1e-12;

// The cheapest measured setting whose worst RMS error is at most accuracy_m;
// where no setting is that accurate (below the most accurate one measured),
// the most accurate one, and the description says so. Throws
// std::invalid_argument, naming the value and the range, unless
// kMostAccuracy_m < accuracy_m < kLeastAccuracy_m (NaN included).
IntegratorChoice integrator_for_accuracy(double accuracy_m);

// The measured error to expect of `settings`: the worst RMS error of the
// most accurate frontier setting of the same method that `settings` is at
// least as tight as (rtol, atol and slip_tol no larger). nullopt where no such setting
// was measured: tolerances looser than every measured one, or a method the
// frontier does not hold (fixed-step rk4).
std::optional<double> expected_error_m(const IntegratorSettings& settings);

}  // namespace rover
