// Hub motors (docs/model.md §5): the steering servo (position control with
// end-stops) and the wheel drive (velocity control with smooth saturation).
#pragma once

#include <cmath>

#include "core/rover_parameters.hpp"
#include "core/s_structure.hpp"

namespace rover {

// tau = -K_d (d - d_ref) - D_d dd/dt - k_stop * (excess beyond +-limit).
inline JointTorque steering_torque(double angle_rad, double rate_radps, double reference_rad,
                                   const SteeringParameters& s) {
  JointTorque t{-s.stiffness_Nm_per_rad * (angle_rad - reference_rad) -
                    s.damping_Nms_per_rad * rate_radps,
                -s.stiffness_Nm_per_rad, -s.damping_Nms_per_rad};
  const double excess = angle_rad > s.limit_rad    ? angle_rad - s.limit_rad
                        : angle_rad < -s.limit_rad ? angle_rad + s.limit_rad
                                                   : 0.0;
  if (excess != 0.0) {
    t.torque_Nm -= s.end_stop_stiffness_Nm_per_rad * excess;
    t.d_angle -= s.end_stop_stiffness_Nm_per_rad;
  }
  return t;
}

// Elastic energy of the servo spring and the end-stop, relative to d = d_ref.
inline double steering_potential(double angle_rad, double reference_rad,
                                 const SteeringParameters& s) {
  const double e = angle_rad - reference_rad;
  const double excess = angle_rad > s.limit_rad    ? angle_rad - s.limit_rad
                        : angle_rad < -s.limit_rad ? angle_rad + s.limit_rad
                                                   : 0.0;
  return 0.5 * s.stiffness_Nm_per_rad * e * e + 0.5 * s.end_stop_stiffness_Nm_per_rad * excess * excess;
}

// tau = tau_max tanh(-K_w (dz/dt - w_ref) / tau_max); zero when K_w = 0.
inline JointTorque drive_torque(double rate_radps, double reference_radps,
                                const DriveParameters& d) {
  if (d.gain_Nms_per_rad == 0.0 || d.max_torque_Nm <= 0.0) return {};
  const double th = std::tanh(-d.gain_Nms_per_rad * (rate_radps - reference_radps) / d.max_torque_Nm);
  return {d.max_torque_Nm * th, 0.0, -d.gain_Nms_per_rad * (1.0 - th * th)};
}

}  // namespace rover
