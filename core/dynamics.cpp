// Mass matrix and forcing of Kane's equations (see dynamics.hpp).
#include "core/dynamics.hpp"

#include "core/actuators.hpp"
#include "core/s_structure.hpp"

namespace rover {
namespace {

// A subtree's inertia about the reference point: mass, first moment m (c - ref)
// and rotational inertia (world axes).
struct SpatialInertia {
  double mass;
  Vec3 first_moment;
  Mat3 rotational;
};

// One body's inertia about the reference point (parallel-axis theorem).
void body_inertia_at_reference(double mass, const BodyKinematics& body, const Vec3& com_from_reference,
                               SpatialInertia& s) {
  s.mass = mass;
  s.first_moment = mass * com_from_reference;
  set_inertia_about_offset(mass, body.inertia, com_from_reference, s.rotational);
}

}  // namespace

CoordinateMatrix mass_matrix(const KinematicTree& tree, const TreeKinematics& kin) {
  CoordinateMatrix M;
  mass_matrix(tree, kin, M);
  return M;
}

void mass_matrix(const KinematicTree& tree, const TreeKinematics& kin, CoordinateMatrix& M) {
  // Composite inertias of every subtree: a node's own body first; its
  // children (later nodes) add theirs before the node is reached below.
  std::array<SpatialInertia, kNumTreeNodes> composite;
  for (int i = 0; i < kNumTreeNodes; ++i) {
    const int b = tree.nodes[i].body;
    if (b >= 0) {
      const BodyKinematics& body = kin.bodies[b];
      body_inertia_at_reference(tree.bodies[b].mass_kg, body,
                                kin.nodes[i].origin + body.com_offset - kin.reference, composite[i]);
    } else {
      composite[i].mass = 0.0;
      composite[i].first_moment.setZero();
      composite[i].rotational.setZero();
    }
  }

  M.setZero();
  for (int i = kNumTreeNodes - 1; i >= 0; --i) {
    const SpatialInertia& c = composite[i];  // complete: every descendant comes after i
    const NodeKinematics& n = kin.nodes[i];
    const int ci = tree.nodes[i].coordinate;
    // Momentum (angular about ref; linear) of subtree i under unit motion of
    // joint i, projected on the unit motion of each joint on its path. (Two
    // 3-vectors: a 6-vector written in halves and read at once in pairs
    // would wait for its stores.)
    const Vec3 angular = c.rotational * n.motion_omega + c.first_moment.cross(n.motion_velocity);
    const Vec3 linear = c.mass * n.motion_velocity + n.motion_omega.cross(c.first_moment);
    M(ci, ci) += n.motion_omega.dot(angular) + n.motion_velocity.dot(linear);
    for (int a = 1; a < tree.path_length[i]; ++a) {  // the proper ancestors
      const int j = tree.path[i][a];
      const int cj = tree.nodes[j].coordinate;
      const double value = kin.nodes[j].motion_omega.dot(angular) + kin.nodes[j].motion_velocity.dot(linear);
      M(cj, ci) += value;
      M(ci, cj) += value;
    }
    const int parent = tree.nodes[i].parent;
    if (parent >= 0) {
      composite[parent].mass += c.mass;
      composite[parent].first_moment += c.first_moment;
      composite[parent].rotational += c.rotational;
    }
  }
}

Coordinates gravity_and_inertia_forces(const KinematicTree& tree, const TreeKinematics& kin,
                                       double gravity_mps2) {
  // The net wrench on each node's subtree, a node's own body first, then its
  // children's added before it is reached (the reverse of the tree's depth
  // order): ForcingPass's sums.
  ForcingPass pass(tree, kin, gravity_mps2);
  for (int k = kNumTreeNodes - 1; k >= 0; --k) pass.visit(tree.depth_order[k]);
  return pass.inertia_forces();
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
    const BodyKinematics& body = kin.bodies[b];
    const Vec3 v = n.velocity + n.omega.cross(body.com_offset);
    T += 0.5 * tree.bodies[b].mass_kg * v.squaredNorm() + 0.5 * n.omega.dot(body.inertia * n.omega);
  }
  return T;
}

double gravity_potential_energy(const KinematicTree& tree, const TreeKinematics& kin,
                                double gravity_mps2) {
  double V = 0.0;
  for (int b = 0; b < kNumBodies; ++b) {
    const NodeKinematics& n = kin.nodes[tree.body_node[b]];
    V += tree.bodies[b].mass_kg * gravity_mps2 * (n.origin + kin.bodies[b].com_offset).z();
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
