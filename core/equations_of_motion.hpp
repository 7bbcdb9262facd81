// The full equations of motion M(q) du/dt = F(q, u) of the SA model (docs/model.md
// §2): Kane's mass matrix and forcing (dynamics.hpp) with the joint torques and
// the wheel-terrain contact forces (contact.hpp) added to F.
//
// Every evaluation goes through one workspace, filled in stages in a fixed
// order, as MuJoCo's mjData is filled by mj_forward (Todorov et al. 2012):
//   kinematics -> contacts -> M -> F -> factorisation of M and du/dt,
// or, where M itself is not needed, kinematics -> contacts -> F and du/dt in
// one backward pass of the articulated-body recursion.
// Every stage takes its arguments in one order, (model, workspace, inputs, q, u),
// the order of Pinocchio's algo(model, data, q, v) (Carpentier et al. 2019),
// leaving out what the stage does not read. A later stage reads what the
// earlier ones wrote: the right-hand side, the stiff-force Jacobian
// (force_jacobian.hpp), the Rosenbrock stages and the output recorder all use
// the same stages, so F is assembled in one place. The workspace is fixed-size
// (nothing allocates) and belongs to its caller: one per thread.
#pragma once

#include <array>

#include "core/branch_induced_llt.hpp"
#include "core/contact.hpp"
#include "core/dynamics.hpp"
#include "core/model_inputs.hpp"
#include "core/rover_model.hpp"

namespace rover {

struct DynamicsWorkspace {
  // Stage 1, compute_kinematics(): frames, velocities and motion axes of the 24
  // tree nodes at (q, u).
  TreeKinematics kinematics;
  // Stage 2, compute_contacts(): the contacts of the 4 wheels with their normal
  // and friction forces (up to kMaxContactsPerWheel points each).
  std::array<WheelContacts, kNumLegs> contacts;
  // Stage 3, compute_mass_matrix(): M(q), 23 x 23, symmetric positive definite.
  CoordinateMatrix mass_matrix;
  // Stage 4, compute_forcing(): F (23) without the contact forces (gravity,
  // velocity-product inertia terms, joint torques), then F with them.
  Coordinates forcing_without_contact;
  Coordinates forcing;
  // Stage 5, compute_acceleration(): the Cholesky factors of M, without
  // fill-in on the coordinate tree (branch_induced_llt.hpp), and
  // du/dt = M^{-1} F (23).
  BranchInducedLLT mass_factorization;
  Coordinates acceleration;
};

// Stage 1: forward kinematics of the tree.
void compute_kinematics(const RoverModel& model, DynamicsWorkspace& workspace,
                        const Coordinates& q, const Coordinates& u);
// Stage 2: wheel-terrain contacts and their forces (needs stage 1).
void compute_contacts(const RoverModel& model, DynamicsWorkspace& workspace);
// Stage 3: the mass matrix (needs stage 1).
void compute_mass_matrix(const RoverModel& model, DynamicsWorkspace& workspace);
// Stage 4: F without and with the contact forces (needs stages 1 and 2).
void compute_forcing(const RoverModel& model, DynamicsWorkspace& workspace,
                     const ModelInputs& inputs, const Coordinates& q, const Coordinates& u);
// Stage 5: factorises M and solves for du/dt (needs stages 3 and 4).
void compute_acceleration(DynamicsWorkspace& workspace);
// Stage 5 without stage 3: du/dt = M^{-1} F by the articulated-body recursion
// (articulated_body.hpp), which never forms M (needs stages 1 and 4). The
// workspace's mass_matrix and mass_factorization keep what they held. A
// tree the recursion finds degenerate falls back to stages 3 and 5.
void compute_acceleration_articulated(const RoverModel& model, DynamicsWorkspace& workspace);

// Stages 4 and 5 at once, without stage 3: F and du/dt = M^{-1} F in one
// backward pass over the tree (articulated_forcing_and_solve(),
// articulated_body.hpp), which gives F as compute_forcing() does, to the last
// bit (needs stages 1 and 2). As compute_acceleration_articulated(), it
// leaves mass_matrix and mass_factorization as they were, unless the tree is
// degenerate: then stages 4, 3 and 5.
void compute_forcing_and_acceleration_articulated(const RoverModel& model, DynamicsWorkspace& workspace,
                                                  const ModelInputs& inputs, const Coordinates& q,
                                                  const Coordinates& u);

// All five stages at (q, u).
void compute_dynamics(const RoverModel& model, DynamicsWorkspace& workspace,
                      const ModelInputs& inputs, const Coordinates& q, const Coordinates& u);

// The right-hand side of the first-order system x = [q; u]:
// dq/dt = u, du/dt = M(q)^{-1} F(q, u), through compute_dynamics(). The hot
// path of every simulation.
StateVector state_derivative(const RoverModel& model, DynamicsWorkspace& workspace,
                             const ModelInputs& inputs, const StateVector& x);
// The same right-hand side through stages 1, 2 and
// compute_forcing_and_acceleration_articulated(): for integrators that need du/dt but
// not M itself (Dormand-Prince, the Rosenbrock stages). Equal to
// state_derivative() to round-off.
StateVector state_derivative_articulated(const RoverModel& model, DynamicsWorkspace& workspace,
                                         const ModelInputs& inputs, const StateVector& x);

// Contacts of all four wheels with their forces, at given kinematics (the
// work of stage 2).
std::array<WheelContacts, kNumLegs> wheel_contacts(const RoverModel& model,
                                                   const TreeKinematics& kin);

// Generalized contact forces: the sum over wheels and contact points of
// J_P^T (F_n n + F_t).
Coordinates contact_generalized_forces(const RoverModel& model, const TreeKinematics& kin,
                                       const std::array<WheelContacts, kNumLegs>& contacts);

// Total mechanical energy: kinetic + gravity + joint springs (S-structures,
// steering servos and end-stops). Contact and dissipation are not included.
// Fills stage 1 of the workspace.
double mechanical_energy(const RoverModel& model, DynamicsWorkspace& workspace,
                         const ModelInputs& inputs, const Coordinates& q, const Coordinates& u);

}  // namespace rover
