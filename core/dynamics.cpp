// Mass matrix and forcing of Kane's equations (see dynamics.hpp).
#include "core/dynamics.hpp"

#include "core/actuators.hpp"
#include "core/s_structure.hpp"

namespace rover {
namespace {

Mat3 skew_square(const Vec3& d) {  // |d|^2 E - d d^T (parallel-axis term)
  return d.squaredNorm() * Mat3::Identity() - d * d.transpose();
}

// A rigid body's (or a composite's) inertia about the reference point.
struct SpatialInertia {
  double mass = 0.0;
  Vec3 first_moment = Vec3::Zero();  // m (c - ref)
  Mat3 rotational = Mat3::Zero();    // inertia about ref, world axes
};

SpatialInertia body_inertia_at_reference(const RigidBodyParameters& body,
                                         const NodeKinematics& frame, const Vec3& reference) {
  const Vec3 d = frame.origin + frame.rotation * body.com_m - reference;
  SpatialInertia s;
  s.mass = body.mass_kg;
  s.first_moment = body.mass_kg * d;
  s.rotational = frame.rotation * body.inertia_kgm2 * frame.rotation.transpose() +
                 body.mass_kg * skew_square(d);
  return s;
}

}  // namespace

CoordinateMatrix mass_matrix(const KinematicTree& tree, const TreeKinematics& kin) {
  // Composite inertias of every subtree, leaves first.
  std::array<SpatialInertia, kNumTreeNodes> composite;
  for (int i = 0; i < kNumTreeNodes; ++i)
    if (tree.nodes[i].body >= 0)
      composite[i] = body_inertia_at_reference(tree.bodies[tree.nodes[i].body], kin.nodes[i],
                                               kin.reference);
  for (int i = kNumTreeNodes - 1; i > 0; --i) {
    const int parent = tree.nodes[i].parent;
    if (parent < 0) continue;
    composite[parent].mass += composite[i].mass;
    composite[parent].first_moment += composite[i].first_moment;
    composite[parent].rotational += composite[i].rotational;
  }

  CoordinateMatrix M = CoordinateMatrix::Zero();
  for (int i = 0; i < kNumTreeNodes; ++i) {
    const SpatialInertia& c = composite[i];
    const NodeKinematics& n = kin.nodes[i];
    // Momentum (linear, angular about ref) of subtree i under unit motion of joint i.
    const Vec3 linear = c.mass * n.motion_velocity + n.motion_omega.cross(c.first_moment);
    const Vec3 angular = c.rotational * n.motion_omega + c.first_moment.cross(n.motion_velocity);
    const int ci = tree.nodes[i].coordinate;
    for (int a = 0; a < tree.path_length[i]; ++a) {
      const int j = tree.path[i][a];
      const NodeKinematics& m = kin.nodes[j];
      const double value = m.motion_omega.dot(angular) + m.motion_velocity.dot(linear);
      const int cj = tree.nodes[j].coordinate;
      M(cj, ci) += value;
      if (j != i) M(ci, cj) += value;
    }
  }
  return M;
}

Coordinates gravity_and_inertia_forces(const KinematicTree& tree, const TreeKinematics& kin,
                                       double gravity_mps2) {
  // Net wrench (force, moment about ref) on each node's subtree, leaves first.
  std::array<Vec3, kNumTreeNodes> force, moment;
  const Vec3 gravity(0.0, 0.0, -gravity_mps2);
  for (int i = 0; i < kNumTreeNodes; ++i) {
    force[i].setZero();
    moment[i].setZero();
    const int b = tree.nodes[i].body;
    if (b < 0) continue;
    const RigidBodyParameters& body = tree.bodies[b];
    const NodeKinematics& n = kin.nodes[i];
    const Vec3 rho = n.rotation * body.com_m;
    const Vec3 com_accel = n.accel_bias + n.alpha_bias.cross(rho) + n.omega.cross(n.omega.cross(rho));
    const Mat3 inertia = n.rotation * body.inertia_kgm2 * n.rotation.transpose();
    // Active gravity minus the inertia force and torque of paper eq. 4 at du/dt = 0.
    force[i] = body.mass_kg * (gravity - com_accel);
    const Vec3 torque = -(inertia * n.alpha_bias + n.omega.cross(inertia * n.omega));
    moment[i] = torque + (n.origin + rho - kin.reference).cross(force[i]);
  }
  Coordinates F = Coordinates::Zero();
  for (int i = kNumTreeNodes - 1; i >= 0; --i) {
    const NodeKinematics& n = kin.nodes[i];
    F[tree.nodes[i].coordinate] += n.motion_omega.dot(moment[i]) + n.motion_velocity.dot(force[i]);
    const int parent = tree.nodes[i].parent;
    if (parent >= 0) {
      force[parent] += force[i];
      moment[parent] += moment[i];
    }
  }
  return F;
}

Coordinates joint_forces(const RoverParameters& p, const ModelInputs& in, const Coordinates& q,
                         const Coordinates& u) {
  Coordinates Q = Coordinates::Zero();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    for (int i = 0; i < 2; ++i) {
      const int c = coord::s_joint(leg, i);
      Q[c] = s_structure_torque(q[c], u[c], in.preload_Nm[2 * leg + i], in.sharpness_f,
                                p.s_structure.stiffness_Nm_per_rad, in.damping_c_q)
                 .torque_Nm;
    }
    const int d = coord::steer(leg);
    Q[d] = steering_torque(q[d], u[d], in.steer_ref_rad[leg], p.steering).torque_Nm;
    const int w = coord::spin(leg);
    Q[w] = drive_torque(u[w], in.wheel_speed_ref_radps[leg], p.drive).torque_Nm;
  }
  return Q;
}

double kinetic_energy(const KinematicTree& tree, const TreeKinematics& kin) {
  double T = 0.0;
  for (int b = 0; b < kNumBodies; ++b) {
    const NodeKinematics& n = kin.nodes[tree.body_node[b]];
    const RigidBodyParameters& body = tree.bodies[b];
    const Vec3 v = n.velocity + n.omega.cross(n.rotation * body.com_m);
    const Vec3 w_body = n.rotation.transpose() * n.omega;
    T += 0.5 * body.mass_kg * v.squaredNorm() + 0.5 * w_body.dot(body.inertia_kgm2 * w_body);
  }
  return T;
}

double gravity_potential_energy(const KinematicTree& tree, const TreeKinematics& kin,
                                double gravity_mps2) {
  double V = 0.0;
  for (int b = 0; b < kNumBodies; ++b) {
    const NodeKinematics& n = kin.nodes[tree.body_node[b]];
    V += tree.bodies[b].mass_kg * gravity_mps2 * (n.origin + n.rotation * tree.bodies[b].com_m).z();
  }
  return V;
}

double joint_potential_energy(const RoverParameters& p, const ModelInputs& in, const Coordinates& q) {
  double V = 0.0;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    for (int i = 0; i < 2; ++i)
      V += s_structure_potential(q[coord::s_joint(leg, i)], in.preload_Nm[2 * leg + i],
                                 in.sharpness_f, p.s_structure.stiffness_Nm_per_rad);
    V += steering_potential(q[coord::steer(leg)], in.steer_ref_rad[leg], p.steering);
  }
  return V;
}

}  // namespace rover
