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

#include <array>

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
// The same, written into M (every entry) without a copy.
void mass_matrix(const KinematicTree& tree, const TreeKinematics& kin, CoordinateMatrix& M);

// The wrench of gravity minus one body's inertia force and torque at
// du/dt = 0 (paper eq. 4): `force` on the body, `moment` about the reference
// point of `kin`. Summed over the tree by ForcingPass, which serves both
// gravity_and_inertia_forces() and the single backward pass of
// articulated_body.hpp, so that both give the same F.
inline void gravity_and_inertia_wrench(double mass_kg, const BodyKinematics& body, const NodeKinematics& n,
                                       const Vec3& reference, const Vec3& gravity, Vec3& moment,
                                       Vec3& force) {
  const Vec3& rho = body.com_offset;
  const Vec3 com_accel = n.accel_bias + n.alpha_bias.cross(rho) + n.omega.cross(n.omega.cross(rho));
  force = mass_kg * (gravity - com_accel);
  const Vec3 torque = -(body.inertia * n.alpha_bias + n.omega.cross(body.inertia * n.omega));
  moment = torque + (n.origin + rho - reference).cross(force);
}

// Kane's forcing in one backward pass over the tree, a node at a time,
// leaves first (every child visited before its parent): the net wrench of
// gravity and the inertia forces on the node's subtree, projected on the
// node's unit motion. Once every node is visited, inertia_forces() is
// gravity_and_inertia_forces() (which is this pass in the reverse of the depth
// order), and complete() adds the joint and contact terms in the
// order of compute_forcing(): the articulated-body pass (articulated_body.hpp)
// gives the same F as the mass-matrix path.
class ForcingPass {
 public:
  ForcingPass(const KinematicTree& tree, const TreeKinematics& kin, double gravity_mps2)
      : tree_(tree), kin_(kin) {
    const Vec3 gravity(0.0, 0.0, -gravity_mps2);
    for (int i = 0; i < kNumTreeNodes; ++i) {
      const int b = tree.nodes[i].body;
      if (b < 0) {
        moment_[i].setZero();
        force_[i].setZero();
        continue;
      }
      gravity_and_inertia_wrench(tree.bodies[b].mass_kg, kin.bodies[b], kin.nodes[i], kin.reference, gravity,
                                 moment_[i], force_[i]);
    }
  }

  void visit(int i) {
    const NodeKinematics& n = kin_.nodes[i];
    inertia_[tree_.nodes[i].coordinate] += n.motion_omega.dot(moment_[i]) + n.motion_velocity.dot(force_[i]);
    const int parent = tree_.nodes[i].parent;
    if (parent >= 0) {
      moment_[parent] += moment_[i];
      force_[parent] += force_[i];
    }
  }

  // F without and with the contact forces at coordinate c, once every node
  // of c is visited: inertia + joint, then + contact.
  void complete(int c, const Coordinates& joint_forces, const Coordinates& contact_forces,
                Coordinates& forcing_without_contact, Coordinates& forcing) const {
    forcing_without_contact[c] = inertia_[c] + joint_forces[c];
    forcing[c] = forcing_without_contact[c] + contact_forces[c];
  }

  const Coordinates& inertia_forces() const { return inertia_; }

 private:
  const KinematicTree& tree_;
  const TreeKinematics& kin_;
  std::array<Vec3, kNumTreeNodes> moment_, force_;
  Coordinates inertia_ = Coordinates::Zero();
};

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
