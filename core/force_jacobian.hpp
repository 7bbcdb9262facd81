// Derivatives of the stiff applied forces of the SA model with respect to the
// generalized coordinates q and speeds u (docs/model.md §5 and §6),
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
//       dQ/dq ~ J_P^T [(df/dv_P) (dv_P/dq) + (df/dp) (dp/dq)],  dp/dq = -n^T J_P,
//     since dp/dt = -v_P . n (docs/model.md §6.3) and u = dq/dt. dv_P/dq at fixed u
//     is how the slip and penetration rates change as the joints turn the
//     wheel and as P slides over the rim (kinematic_tree.hpp,
//     contact_point_position_derivative()): a joint moving at 1 rad/s turns
//     v_P by about 1 m/s per rad, which the stuck friction (mu'(0) F_n) turns
//     into ~1e4 N/rad, ~1e6 N/rad with v_s a hundred times smaller. Left out of
//     dQ/dq are the non-stiff terms: the turning of J_P and n with q at a
//     fixed force (|f| times a lever, ~1 N m/rad against ~1e3 N m/rad).
// The gravity and the velocity-dependent inertia forces are not stiff and are
// not differentiated. A W-method (which stays accurate with an approximate
// Jacobian) is what these derivatives are meant for.
#pragma once

#include <array>

#include "core/contact.hpp"
#include "core/coordinates.hpp"
#include "core/equations_of_motion.hpp"
#include "core/model_inputs.hpp"
#include "core/rover_model.hpp"

namespace rover {

// Derivatives of the force f = F_n n + F_t that one contact applies to the
// wheel (docs/model.md §6.4-6.5), at fixed normal n.
struct ContactForceDerivatives {
  Mat3 d_force_d_velocity = Mat3::Zero();     // df/dv_P at fixed p [N s/m]
  Vec3 d_force_d_penetration = Vec3::Zero();  // df/dp at fixed v_P [N/m]
};

// Zero where the normal force is clamped at 0 (no contact force). At zero slip
// the friction derivative is its limit mu'(0) F_n on the tangent plane.
// `contact` as compute_contact_forces() left it (mu and mu' come from its
// friction_tanh).
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
  // The diagonal of the springs' part of K alone (S-structures, steering
  // servos, contact normal springs), without the turning of the slip with q:
  // sqrt(-k_cc / M_cc) is the frequency at which coordinate c rings on them.
  // The friction part of K is no spring (it turns a damping force; the
  // motion it drives is a creep at the rate K/D, not an oscillation).
  Coordinates spring_d_position_diagonal = Coordinates::Zero();
};

// Reads stages 1 and 2 (kinematics, contacts) of `workspace`, which must have
// been filled at the same (q, u) (core/equations_of_motion.hpp).
StiffForceJacobian stiff_force_jacobian(const RoverModel& model, const DynamicsWorkspace& workspace,
                                        const ModelInputs& inputs, const Coordinates& q,
                                        const Coordinates& u);

// The same, written into the caller's matrices (overwritten, every entry)
// without a copy: D into d_speed, K into d_position.
void stiff_force_jacobian(const RoverModel& model, const DynamicsWorkspace& workspace, const ModelInputs& inputs,
                          const Coordinates& q, const Coordinates& u, CoordinateMatrix& d_speed,
                          CoordinateMatrix& d_position, Coordinates& spring_d_position_diagonal);

}  // namespace rover
