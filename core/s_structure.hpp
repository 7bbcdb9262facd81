// Lumped S-structure joint: preloaded non-linear torsional spring and viscous
// damper (paper eq. 1 plus the c_q term; docs/model.md §5):
//   tau(b, db) = -(2 M0 / pi) atan(f b) - k_q b - c_q db
// with its partial derivatives and the potential energy of the elastic part.
#pragma once

#include <cmath>
#include <numbers>

namespace rover {

struct JointTorque {
  double torque_Nm = 0.0;
  double d_angle = 0.0;   // d tau / d angle   [N m / rad]
  double d_rate = 0.0;    // d tau / d rate    [N m s / rad]
};

// d tau / d angle alone, without the arctangent of the torque (the
// Jacobians and the step control of the stiff integrator want only this).
inline double s_structure_stiffness(double angle_rad, double preload_Nm, double sharpness_f,
                                    double stiffness_k_q) {
  const double fb = sharpness_f * angle_rad;
  const double scale = 2.0 * preload_Nm / std::numbers::pi;
  return -scale * sharpness_f / (1.0 + fb * fb) - stiffness_k_q;
}

inline JointTorque s_structure_torque(double angle_rad, double rate_radps, double preload_Nm,
                                      double sharpness_f, double stiffness_k_q,
                                      double damping_c_q) {
  const double fb = sharpness_f * angle_rad;
  const double scale = 2.0 * preload_Nm / std::numbers::pi;
  return {-scale * std::atan(fb) - stiffness_k_q * angle_rad - damping_c_q * rate_radps,
          s_structure_stiffness(angle_rad, preload_Nm, sharpness_f, stiffness_k_q), -damping_c_q};
}

// V(b) with dV/db = (2 M0/pi) atan(f b) + k_q b, V(0) = 0.
inline double s_structure_potential(double angle_rad, double preload_Nm, double sharpness_f,
                                    double stiffness_k_q) {
  const double fb = sharpness_f * angle_rad;
  const double scale = 2.0 * preload_Nm / std::numbers::pi;
  return scale * (angle_rad * std::atan(fb) - std::log1p(fb * fb) / (2.0 * sharpness_f)) +
         0.5 * stiffness_k_q * angle_rad * angle_rad;
}

}  // namespace rover
