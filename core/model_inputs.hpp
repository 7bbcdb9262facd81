// The inputs a study varies between runs (f, c_q and the eight preloads M0,
// docs/model.md §5) plus the actuator set-points of a scenario. Everything
// else is fixed by RoverParameters.
#pragma once

#include <array>

#include "core/rover_parameters.hpp"

namespace rover {

struct ModelInputs {
  double sharpness_f = 1e4;                       // S-structure f [1/rad]
  double damping_c_q = 0.14;                      // S-structure c_q [N m s/rad]
  std::array<double, kNumSJoints> preload_Nm{};   // M0, order (1,1), (1,2), ..., (4,2)
  std::array<double, kNumLegs> wheel_speed_ref_radps{};  // w_ref per wheel
  std::array<double, kNumLegs> steer_ref_rad{};          // d_ref per wheel
};

// f, c_q and the mean preloads of `parameters`; zero set-points.
inline ModelInputs nominal_inputs(const RoverParameters& parameters) {
  ModelInputs in;
  in.sharpness_f = parameters.s_structure.sharpness_f;
  in.damping_c_q = parameters.s_structure.damping_c_q;
  in.preload_Nm = parameters.s_structure.preload_mean_Nm;
  return in;
}

}  // namespace rover
