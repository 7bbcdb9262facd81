// Kane's equations of the SA model (paper eqs. 2-6; docs/model.md §2 and §5):
//   M(q) du/dt = F(q, u),
// where F = F_r (active forces: gravity, joint torques, contact) plus the
// velocity-dependent part of the generalized inertia forces F_r*.
//
// With every twist and wrench taken about one world point (the chassis origin),
// Kane's sums over bodies reduce to a composite-body pass for M and a single
// backward pass for F: each partial velocity is the unit motion of one node of
// the kinematic tree, dotted with the net wrench of the subtree it carries.
#pragma once

#include "core/coordinates.hpp"
#include "core/kinematic_tree.hpp"
#include "core/model_inputs.hpp"

namespace rover {

// A body's rotational inertia about a point at `offset` from its centre of
// mass (parallel-axis theorem), I_com + m (|d|^2 E - d d^T), written on one
// triangle so that it stays exactly symmetric, into the 3 x 3 matrix or
// block `I` (a block of a larger matrix is written in place: a copy of a
// freshly written 3 x 3 would read it back before its stores are done).
// Used by mass_matrix() and articulated_body_solve().
template <class Matrix3>
inline void set_inertia_about_offset(double mass_kg, const Mat3& inertia_com, const Vec3& offset,
                                     Matrix3&& I) {
  const Vec3& d = offset;
  const double d_squared = d.squaredNorm();
  for (int c = 0; c < 3; ++c) {
    I(c, c) = inertia_com(c, c) + mass_kg * (d_squared - d[c] * d[c]);
    for (int r = c + 1; r < 3; ++r) I(r, c) = I(c, r) = inertia_com(r, c) - mass_kg * d[r] * d[c];
  }
}

inline Mat3 inertia_about_offset(double mass_kg, const Mat3& inertia_com, const Vec3& offset) {
  Mat3 I;
  set_inertia_about_offset(mass_kg, inertia_com, offset, I);
  return I;
}

// M(q): sum over bodies of m J_v^T J_v + J_w^T I J_w (symmetric positive definite).
CoordinateMatrix mass_matrix(const KinematicTree& tree, const TreeKinematics& kin);

// Gravity plus the velocity-dependent inertia forces (F_r* at du/dt = 0).
Coordinates gravity_and_inertia_forces(const KinematicTree& tree, const TreeKinematics& kin,
                                       double gravity_mps2);

// Generalized forces of the joints: S-structure springs and dampers, steering
// servos with end-stops, wheel drives. The bogie pivot is ideal.
Coordinates joint_forces(const RoverParameters& parameters, const ModelInputs& inputs,
                         const Coordinates& q, const Coordinates& u);

// Energies, for conservation checks and diagnostics.
double kinetic_energy(const KinematicTree& tree, const TreeKinematics& kin);
double gravity_potential_energy(const KinematicTree& tree, const TreeKinematics& kin,
                                double gravity_mps2);
// Elastic energy of the S-structures and the steering springs and end-stops.
double joint_potential_energy(const RoverParameters& parameters, const ModelInputs& inputs,
                              const Coordinates& q);

}  // namespace rover
