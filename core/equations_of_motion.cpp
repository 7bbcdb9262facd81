// The stages of the equations of motion (see equations_of_motion.hpp).
#include "core/equations_of_motion.hpp"

#include "core/articulated_body.hpp"

namespace rover {

namespace {

void fill_wheel_contacts(const RoverModel& model, const TreeKinematics& kin,
                         std::array<WheelContacts, kNumLegs>& contacts) {
  for (int leg = 0; leg < kNumLegs; ++leg) {
    find_leg_wheel_contacts(model.terrain, kin, leg, model.parameters.geometry.wheel_radius_m, contacts[leg]);
    compute_contact_forces(kin, node::wheel(leg), model.parameters.contact,
                           model.parameters.friction, contacts[leg]);
  }
}

}  // namespace

std::array<WheelContacts, kNumLegs> wheel_contacts(const RoverModel& model,
                                                   const TreeKinematics& kin) {
  std::array<WheelContacts, kNumLegs> contacts;
  fill_wheel_contacts(model, kin, contacts);
  return contacts;
}

Coordinates contact_generalized_forces(const RoverModel& model, const TreeKinematics& kin,
                                       const std::array<WheelContacts, kNumLegs>& contacts) {
  Coordinates Q = Coordinates::Zero();
  for (int leg = 0; leg < kNumLegs; ++leg)
    for (int k = 0; k < contacts[leg].count; ++k) {
      const ContactPoint& c = contacts[leg].points[k];
      add_point_force(model.tree, kin, node::wheel(leg), c.point_m,
                      c.normal_force_N * c.normal + c.friction_force_N, Q);
    }
  return Q;
}

void compute_kinematics(const RoverModel& model, DynamicsWorkspace& workspace,
                        const Coordinates& q, const Coordinates& u) {
  forward_kinematics(model.tree, q, u, workspace.kinematics);
}

void compute_contacts(const RoverModel& model, DynamicsWorkspace& workspace) {
  fill_wheel_contacts(model, workspace.kinematics, workspace.contacts);
}

void compute_mass_matrix(const RoverModel& model, DynamicsWorkspace& workspace) {
  mass_matrix(model.tree, workspace.kinematics, workspace.mass_matrix);
}

void compute_forcing(const RoverModel& model, DynamicsWorkspace& workspace,
                     const ModelInputs& inputs, const Coordinates& q, const Coordinates& u) {
  workspace.forcing_without_contact =
      gravity_and_inertia_forces(model.tree, workspace.kinematics, model.parameters.gravity_mps2) +
      joint_forces(model.parameters, inputs, q, u);
  workspace.forcing = workspace.forcing_without_contact +
                      contact_generalized_forces(model, workspace.kinematics, workspace.contacts);
}

void compute_acceleration(DynamicsWorkspace& workspace) {
  workspace.mass_factorization.compute(workspace.mass_matrix);
  workspace.acceleration = workspace.mass_factorization.solve(workspace.forcing);
}

void compute_acceleration_articulated(const RoverModel& model, DynamicsWorkspace& workspace) {
  if (const std::optional<Coordinates> a = articulated_body_solve(model.tree, workspace.kinematics, workspace.forcing)) {
    workspace.acceleration = *a;
    return;
  }
  compute_mass_matrix(model, workspace);
  compute_acceleration(workspace);
}

void compute_dynamics(const RoverModel& model, DynamicsWorkspace& workspace,
                      const ModelInputs& inputs, const Coordinates& q, const Coordinates& u) {
  compute_kinematics(model, workspace, q, u);
  compute_contacts(model, workspace);
  compute_mass_matrix(model, workspace);
  compute_forcing(model, workspace, inputs, q, u);
  compute_acceleration(workspace);
}

StateVector state_derivative(const RoverModel& model, DynamicsWorkspace& workspace,
                             const ModelInputs& inputs, const StateVector& x) {
  const Coordinates q = x.head<kNumCoordinates>();
  const Coordinates u = x.tail<kNumCoordinates>();
  compute_dynamics(model, workspace, inputs, q, u);
  StateVector dx;
  dx << u, workspace.acceleration;
  return dx;
}

void compute_forcing_and_acceleration_articulated(const RoverModel& model, DynamicsWorkspace& workspace,
                                                  const ModelInputs& inputs, const Coordinates& q,
                                                  const Coordinates& u) {
  if (articulated_forcing_and_solve(model.tree, workspace.kinematics, model.parameters.gravity_mps2,
                                    joint_forces(model.parameters, inputs, q, u),
                                    contact_generalized_forces(model, workspace.kinematics, workspace.contacts),
                                    workspace.forcing_without_contact, workspace.forcing, workspace.acceleration))
    return;
  compute_forcing(model, workspace, inputs, q, u);
  compute_mass_matrix(model, workspace);
  compute_acceleration(workspace);
}

StateVector state_derivative_articulated(const RoverModel& model, DynamicsWorkspace& workspace,
                                         const ModelInputs& inputs, const StateVector& x) {
  const Coordinates q = x.head<kNumCoordinates>();
  const Coordinates u = x.tail<kNumCoordinates>();
  compute_kinematics(model, workspace, q, u);
  compute_contacts(model, workspace);
  compute_forcing_and_acceleration_articulated(model, workspace, inputs, q, u);
  StateVector dx;
  dx << u, workspace.acceleration;
  return dx;
}

double mechanical_energy(const RoverModel& model, DynamicsWorkspace& workspace,
                         const ModelInputs& inputs, const Coordinates& q, const Coordinates& u) {
  compute_kinematics(model, workspace, q, u);
  return kinetic_energy(model.tree, workspace.kinematics) +
         gravity_potential_energy(model.tree, workspace.kinematics, model.parameters.gravity_mps2) +
         joint_potential_energy(model.parameters, inputs, q);
}

}  // namespace rover
