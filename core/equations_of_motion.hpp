// The full equations of motion M(q) du/dt = F(q, u) of the SA model (MODEL.md
// section 2): Kane's mass matrix and forcing (dynamics.hpp) with the joint
// torques and the wheel-terrain contact forces (contact.hpp) added to F.
#pragma once

#include <array>

#include "core/contact.hpp"
#include "core/dynamics.hpp"
#include "core/model_inputs.hpp"
#include "core/rover_model.hpp"

namespace rover {

struct EquationsOfMotion {
  MassMatrix mass_matrix;
  Coordinates forcing;             // F, contact included
  Coordinates forcing_no_contact;  // F without the contact forces
  std::array<WheelContacts, kNumLegs> contacts;
};

// Everything at one state, for inspection (`rover eom`) and tests.
EquationsOfMotion evaluate_equations_of_motion(const RoverModel& model, const Coordinates& q,
                                               const Coordinates& u, const ModelInputs& inputs);

// F without the contact forces: gravity, inertia (velocity-product) terms and
// the joint torques (S-structures, servos, wheel drives). Every evaluation of
// the equations of motion sums the applied forces through this one function.
Coordinates forcing_without_contact(const RoverModel& model, const ModelInputs& inputs,
                                    const TreeKinematics& kin, const Coordinates& q,
                                    const Coordinates& u);

// Contacts of all four wheels with their forces, at given kinematics.
std::array<WheelContacts, kNumLegs> wheel_contacts(const RoverModel& model,
                                                   const TreeKinematics& kin);

// Generalized contact forces sum over wheels and regions of J_P^T (F_n n + F_t).
Coordinates contact_generalized_forces(const RoverModel& model, const TreeKinematics& kin,
                                       const std::array<WheelContacts, kNumLegs>& contacts);

// The right-hand side of the first-order system x = [q; u]:
// dq/dt = u, du/dt = M(q)^{-1} F(q, u). The hot path of every simulation.
StateVector state_derivative(const RoverModel& model, const ModelInputs& inputs,
                             const StateVector& x);

// Total mechanical energy: kinetic + gravity + joint springs (S-structures,
// steering servos and end-stops). Contact and dissipation are not included.
double mechanical_energy(const RoverModel& model, const ModelInputs& inputs, const Coordinates& q,
                         const Coordinates& u);

}  // namespace rover
