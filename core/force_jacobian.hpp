// Derivatives of the stiff applied forces of the SA model with respect to the
// generalized coordinates q and speeds u (issue 7; MODEL.md sections 5 and 6),
// for the linearly implicit integrator (core/integrator_rosenbrock.cpp).
//
// The stiffness of the model sits in a few force elements:
//   * the S-structure springs near zero deflection (slope 2 M0 f / pi) and
//     their dampers, the steering servos and end-stops, the wheel drives:
//     each acts on its own coordinate, so dQ/dq and dQ/du are diagonal;
//   * the wheel-terrain contacts: a Kelvin-Voigt normal force and the steep
//     Makkar friction (mu'(0) F_n is about 9e3 N s/m on a loaded wheel).
//     With f = F_n n + F_t applied at P and Q = J_P(q)^T f:
//       dQ/du = J_P^T (df/dv_P) J_P                    (exact: v_P = J_P(q) u)
//       dQ/dq ~ J_P^T (df/dp) (dp/dq),  dp/dq = -n^T J_P,
//     since dp/dt = -v_P . n (MODEL.md 6.3) and u = dq/dt. Left out of dQ/dq
//     are the non-stiff terms: the turning of J_P and n with q at a fixed
//     force (|f| times a lever, ~1 N m/rad against ~1e3 N m/rad) and the
//     change of v_P = J_P(q) u with q (zero at rest).
// The gravity and the velocity-dependent inertia forces are not stiff and are
// not differentiated. A W-method (which stays accurate with an approximate
// Jacobian) is what these derivatives are meant for.
#pragma once

#include <array>

#include "core/contact.hpp"
#include "core/coordinates.hpp"
#include "core/model_inputs.hpp"
#include "core/rover_model.hpp"

namespace rover {

using CoordinateMatrix = Eigen::Matrix<double, kNumCoordinates, kNumCoordinates>;

// Derivatives of the force f = F_n n + F_t that one contact applies to the
// wheel (MODEL.md 6.4-6.5), at fixed normal n.
struct ContactForceDerivatives {
  Mat3 d_force_d_velocity = Mat3::Zero();     // df/dv_P at fixed p [N s/m]
  Vec3 d_force_d_penetration = Vec3::Zero();  // df/dp at fixed v_P [N/m]
};

// Zero where the normal force is clamped at 0 (no contact force). At zero slip
// the friction derivative is its limit mu'(0) F_n on the tangent plane.
ContactForceDerivatives contact_force_derivatives(const ContactPoint& contact,
                                                  const ContactParameters& parameters,
                                                  const FrictionParameters& friction);

// Diagonal derivatives of joint_forces() (core/dynamics.hpp): entry c is
// dQ_c/dq_c resp. dQ_c/du_c; every other entry of dQ/dq and dQ/du is zero.
struct JointForceDerivatives {
  Coordinates d_position = Coordinates::Zero();  // [N m/rad]
  Coordinates d_speed = Coordinates::Zero();     // [N m s/rad]
};

JointForceDerivatives joint_force_derivatives(const RoverParameters& parameters,
                                              const ModelInputs& inputs, const Coordinates& q,
                                              const Coordinates& u);

// D = dF/du and K ~ dF/dq of the stiff generalized forces: the joint forces
// and the contact forces (see the top of this file for what K leaves out).
struct StiffForceJacobian {
  CoordinateMatrix d_speed = CoordinateMatrix::Zero();     // D
  CoordinateMatrix d_position = CoordinateMatrix::Zero();  // K
};

// `kin` and `contacts` are those of the state (q, u), as computed by
// forward_kinematics() and wheel_contacts() (core/equations_of_motion.hpp).
StiffForceJacobian stiff_force_jacobian(const RoverModel& model, const ModelInputs& inputs,
                                        const Coordinates& q, const Coordinates& u,
                                        const TreeKinematics& kin,
                                        const std::array<WheelContacts, kNumLegs>& contacts);

}  // namespace rover
