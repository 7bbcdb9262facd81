// du/dt = M(q)^{-1} tau without forming M: the articulated-body recursion
// (R. Featherstone, Rigid Body Dynamics Algorithms, Springer 2008, §7.3) on
// the rover's kinematic tree (docs/model.md §3), in the world frame with every
// motion and momentum taken about the reference point of TreeKinematics, as
// the mass matrix of dynamics.hpp is.
//
// With the velocity-product and gravity terms already in the generalized
// force tau (they are in the forcing F of Kane's equations, docs/model.md
// §2), the recursion solves M a = tau alone: all its bias terms vanish.
//   * Legs, leaves first: each leg joint i (one node per coordinate) with unit
//     motion S_i and the articulated inertia I^A_i of the bodies below it
//     (its own and its children's) gives U_i = I^A_i S_i, D_i = S_i^T U_i and
//     u_i = tau_i - S_i^T p^A_i, and passes I^A_i - U_i U_i^T / D_i and
//     p^A_i + U_i u_i / D_i to its parent (Featherstone's pass 2, with no
//     coordinate transform, as everything is in one frame).
//   * Trunk: the seven coordinates above the legs (the floating base x .. psi
//     and the bogie phi, which drives two nodes, docs/model.md's lever
//     coupling) carry the articulated inertias and biases of the chassis and
//     of the two bogies with their legs; the composite-rigid-body algorithm
//     over these eight nodes gives the 7 x 7 system A x = tau_trunk - S^T p^C
//     (A is the trunk block of a mass matrix of rigid bodies whose inertias
//     are the articulated ones), solved by Cholesky.
//   * Legs, root first: a_i = a_parent + S_i (u_i - U_i^T a_parent) / D_i
//     (pass 3).
// No M is formed, and no matrix larger than 7 x 7 is factorized.
//
// articulated_forcing_and_solve() runs the backward pass once for both Kane's
// forcing and the recursion: at each node, leaves first, the net wrench of
// gravity and the inertia forces on its subtree (dynamics.hpp) gives the
// node's entry of F, which completes tau_i just before the node's U_i, D_i
// and u_i are formed, and the node's body enters the wrench and the
// articulated inertia in the same visit. F comes out as
// gravity_and_inertia_forces() + joint forces + contact forces gives it, to
// the last bit.
#pragma once

#include <optional>

#include "core/coordinates.hpp"
#include "core/dynamics.hpp"
#include "core/kinematic_tree.hpp"

namespace rover {

// M(q)^{-1} tau at the kinematics `kin`, or nothing if the recursion meets a
// pivot D_i or a trunk matrix that is not positive (a degenerate tree; the
// caller then factorizes M itself).
std::optional<Coordinates> articulated_body_solve(const KinematicTree& tree, const TreeKinematics& kin,
                                                  const Coordinates& generalized_force);

// Kane's forcing and du/dt = M^{-1} F in one backward pass over the tree:
// F = gravity and inertia forces + joint_forces + contact_forces, written
// into forcing_without_contact (without the last term) and forcing, and
// du/dt into acceleration. Returns false for a degenerate tree (as
// articulated_body_solve()); the outputs are then incomplete.
bool articulated_forcing_and_solve(const KinematicTree& tree, const TreeKinematics& kin, double gravity_mps2,
                                   const Coordinates& joint_forces, const Coordinates& contact_forces,
                                   Coordinates& forcing_without_contact, Coordinates& forcing,
                                   Coordinates& acceleration);

}  // namespace rover
