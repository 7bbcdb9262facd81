// See equations_of_motion.hpp.
#include "core/equations_of_motion.hpp"

#include <Eigen/Cholesky>

namespace rover {

std::array<WheelContacts, kNumLegs> wheel_contacts(const RoverModel& model,
                                                   const TreeKinematics& kin) {
  std::array<WheelContacts, kNumLegs> contacts;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const NodeKinematics& wheel = kin.nodes[node::wheel(leg)];
    contacts[leg] = find_wheel_contacts(model.terrain, wheel.origin, wheel.rotation.col(1),
                                        model.parameters.geometry.wheel_radius_m);
    compute_contact_forces(kin, node::wheel(leg), model.parameters.contact,
                           model.parameters.friction, contacts[leg]);
  }
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

Coordinates forcing_without_contact(const RoverModel& model, const ModelInputs& inputs,
                                    const TreeKinematics& kin, const Coordinates& q,
                                    const Coordinates& u) {
  return gravity_and_inertia_forces(model.tree, kin, model.parameters.gravity_mps2) +
         joint_forces(model.parameters, inputs, q, u);
}

EquationsOfMotion evaluate_equations_of_motion(const RoverModel& model, const Coordinates& q,
                                               const Coordinates& u, const ModelInputs& inputs) {
  const TreeKinematics kin = forward_kinematics(model.tree, q, u);
  EquationsOfMotion eom;
  eom.mass_matrix = mass_matrix(model.tree, kin);
  eom.forcing_no_contact = forcing_without_contact(model, inputs, kin, q, u);
  eom.contacts = wheel_contacts(model, kin);
  eom.forcing = eom.forcing_no_contact + contact_generalized_forces(model, kin, eom.contacts);
  return eom;
}

StateVector state_derivative(const RoverModel& model, const ModelInputs& inputs,
                             const StateVector& x) {
  const Coordinates q = x.head<kNumCoordinates>();
  const Coordinates u = x.tail<kNumCoordinates>();
  const TreeKinematics kin = forward_kinematics(model.tree, q, u);
  const Coordinates F = forcing_without_contact(model, inputs, kin, q, u) +
                        contact_generalized_forces(model, kin, wheel_contacts(model, kin));
  StateVector dx;
  dx.head<kNumCoordinates>() = u;
  dx.tail<kNumCoordinates>() = mass_matrix(model.tree, kin).llt().solve(F);
  return dx;
}

double mechanical_energy(const RoverModel& model, const ModelInputs& inputs, const Coordinates& q,
                         const Coordinates& u) {
  const TreeKinematics kin = forward_kinematics(model.tree, q, u);
  return kinetic_energy(model.tree, kin) +
         gravity_potential_energy(model.tree, kin, model.parameters.gravity_mps2) +
         joint_potential_energy(model.parameters, inputs, q);
}

}  // namespace rover
