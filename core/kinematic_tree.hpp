// The rover's kinematic tree (docs/model.md §3) and its kinematics.
//
// The tree is a list of nodes, parents first. Each node is one elementary
// 1-DOF joint (a rotation about, or a translation along, an axis fixed in the
// parent frame after a constant offset) driven by one generalized coordinate
// times a sign. Several nodes may share a coordinate: the two bogies are
// driven by phi with signs +1 (right) and -1 (left), which is docs/model.md's
// lever coupling. The floating chassis is six nodes: translations along the
// world axes, then Rz(theta), Ry(chi), Rx(psi), so R_WC = Rz Ry Rx.
//
// forward_kinematics() evaluates, for every node, the world pose, velocity and
// the "bias" accelerations (the accelerations when du/dt = 0), and for every
// body its centre-of-mass offset and inertia in world axes. They are the
// ingredients of Kane's partial velocities and inertia forces (paper eqs. 3-4).
// Everything is expressed in the world frame; moments are taken about a single
// reference point (the chassis origin) so sums over bodies are plain additions.
#pragma once

#include <array>
#include <vector>

#include "core/coordinates.hpp"
#include "core/rover_parameters.hpp"

namespace rover {

enum class JointType { kRevolute, kPrismatic };

struct TreeNode {
  int parent = -1;                 // index of the parent node, -1 for the world
  Vec3 offset_m = Vec3::Zero();    // joint origin in the parent frame
  JointType type = JointType::kRevolute;
  Vec3 axis = Vec3::UnitZ();       // unit axis in the parent frame
  int coordinate = 0;              // index into q and u
  double sign = 1.0;               // joint displacement = sign * q[coordinate]
  int body = -1;                   // index into KinematicTree::bodies, -1 if massless
};

inline constexpr int kNumTreeNodes = 24;
inline constexpr int kNumBodies = 15;
inline constexpr int kMaxTreeDepth = 12;

// Node indices of the named frames.
namespace node {
inline constexpr int chassis = 5;
inline constexpr int bogie_left = 6, bogie_right = 7;
inline constexpr int module1(int leg) { return 8 + 4 * leg; }
inline constexpr int module2(int leg) { return 9 + 4 * leg; }
inline constexpr int hub(int leg) { return 10 + 4 * leg; }    // after steering
inline constexpr int wheel(int leg) { return 11 + 4 * leg; }  // after rolling
}  // namespace node

struct KinematicTree {
  std::array<TreeNode, kNumTreeNodes> nodes;
  std::array<RigidBodyParameters, kNumBodies> bodies;  // in their node's frame
  std::array<int, kNumBodies> body_node{};
  // Ancestors of each node, the node itself first, root last.
  std::array<std::array<int, kMaxTreeDepth>, kNumTreeNodes> path{};
  std::array<int, kNumTreeNodes> path_length{};
  // The nodes by depth (path length), ties by index: every parent before its
  // children, and the four legs' nodes of one depth next to each other. The
  // articulated-body recursion and its forcing pass visit them in this order
  // (root first) or its reverse (leaves first), so that the four legs'
  // chains of dependent arithmetic (a pivot, its division, the update of the
  // parent) follow one another closely and the processor overlaps them.
  // Siblings keep their relative order, so every sum over a node's children
  // is added in the same order as by index.
  std::array<int, kNumTreeNodes> depth_order{};
  // The tree of the coordinates: coordinate_parent[c] (< c) drives the
  // nearest joint above the nodes of c, -1 at the root. M(q) and the stiff
  // force Jacobians have non-zeros only where one coordinate is an ancestor
  // of the other (branch_induced_lu.hpp).
  std::array<int, kNumCoordinates> coordinate_parent{};
  double total_mass_kg = 0.0;
};

// Builds the tree of docs/model.md §3 from the template parameters.
KinematicTree build_kinematic_tree(const RoverParameters& parameters);

// World pose, velocity and bias acceleration of one node frame.
struct NodeKinematics {
  Mat3 rotation;        // R_W,node
  Vec3 origin;          // world position of the node origin
  Vec3 axis;            // joint axis in world coordinates (unit)
  Vec3 omega;           // angular velocity
  Vec3 velocity;        // velocity of the node origin
  Vec3 alpha_bias;      // angular acceleration at du/dt = 0
  Vec3 accel_bias;      // acceleration of the node origin at du/dt = 0
  // Unit joint motion (times sign) as a twist at the reference point:
  // omega = motion_omega * u_c, v(ref) = motion_velocity * u_c.
  Vec3 motion_omega;
  Vec3 motion_velocity;
};

// World-frame mass distribution of one body, shared by the mass matrix, the
// inertia forces and the energies at one state.
struct BodyKinematics {
  Vec3 com_offset;      // R_W,node com_m: centre of mass relative to the node origin [m]
  Mat3 inertia;         // R_W,node I R_W,node^T: inertia about the centre of mass [kg m^2]
};

struct TreeKinematics {
  std::array<NodeKinematics, kNumTreeNodes> nodes;
  std::array<BodyKinematics, kNumBodies> bodies;  // indexed like KinematicTree::bodies
  Vec3 reference;       // moment reference point (the chassis origin)
};

TreeKinematics forward_kinematics(const KinematicTree& tree, const Coordinates& q,
                                  const Coordinates& u);
// The same, written into `kin` (every field), without a copy of the result.
void forward_kinematics(const KinematicTree& tree, const Coordinates& q, const Coordinates& u,
                        TreeKinematics& kin);

// Only the pose and the velocity of every node (rotation, origin, axis, omega,
// velocity) and the reference point: what positions and point velocities need
// (the outputs of simulate(), the contacts' normal forces), at about half the
// cost. The other fields of `kin` are left as they were.
void forward_pose_and_velocity(const KinematicTree& tree, const Coordinates& q, const Coordinates& u,
                               TreeKinematics& kin);

// World position of the point with body-frame coordinates r_local on `node`.
inline Vec3 point_position(const TreeKinematics& kin, int node_index, const Vec3& r_local) {
  const NodeKinematics& n = kin.nodes[node_index];
  return n.origin + n.rotation * r_local;
}

// Velocity of the material point at world position p, fixed to `node`.
inline Vec3 point_velocity(const TreeKinematics& kin, int node_index, const Vec3& p) {
  const NodeKinematics& n = kin.nodes[node_index];
  return n.velocity + n.omega.cross(p - n.origin);
}

// A 3 x 23 Jacobian of a node's motion on the node's path alone: row a is
// its column of the coordinate of KinematicTree::path[node][a] (the other
// columns are zero: only the joints above a node move it); the rows past the
// path length are zero. The forms below write these rows; the 3 x 23 forms
// spread them into their columns.
using PathJacobian = Eigen::Matrix<double, kMaxTreeDepth, 3>;

// Partial velocities (Jacobian d v_P / d u, 3 x 23) of the material point at
// world position p fixed to `node`.
Eigen::Matrix<double, 3, kNumCoordinates> point_jacobian(const KinematicTree& tree,
                                                         const TreeKinematics& kin,
                                                         int node_index, const Vec3& p);
PathJacobian point_jacobian_on_path(const KinematicTree& tree, const TreeKinematics& kin, int node_index,
                                    const Vec3& p);

// Angular-velocity Jacobian d omega / d u (3 x 23) of the frame of `node`.
Eigen::Matrix<double, 3, kNumCoordinates> angular_jacobian(const KinematicTree& tree,
                                                           const TreeKinematics& kin, int node_index);
PathJacobian angular_jacobian_on_path(const KinematicTree& tree, const TreeKinematics& kin, int node_index);

// How the velocity of a node frame changes with the coordinates at fixed
// speeds: d v_o / dq and d omega / dq (3 x 23 each), o the node origin.
// Joint k of the path (unit twist w_k about its origin o_k) turns every frame
// after it, and moves o under the joints before it and itself:
//   d v_o / dq_k   = w_k x (v_o - v_k - omega_k x (o - o_k)) + omega_k x (w_k x (o - o_k)),
//   d omega / dq_k = w_k x (omega - omega_k),
// with v_k, omega_k the velocity of node k's frame (its own motion included);
// a translation a_k gives omega_k x a_k and 0. For a point P of the node,
// v_P = v_o + omega x (P - o) then changes by
//   d v_o/dq + (d omega/dq) x (P - o) + omega x (dP/dq - do/dq).
struct FrameVelocityPositionDerivative {
  Eigen::Matrix<double, 3, kNumCoordinates> d_origin_velocity;  // [m/s per unit q]
  Eigen::Matrix<double, 3, kNumCoordinates> d_omega;            // [rad/s per unit q]
};
FrameVelocityPositionDerivative frame_velocity_position_derivative(const KinematicTree& tree,
                                                                   const TreeKinematics& kin,
                                                                   int node_index);
struct FrameVelocityPositionDerivativeOnPath {
  PathJacobian d_origin_velocity, d_omega;
};
FrameVelocityPositionDerivativeOnPath frame_velocity_position_derivative_on_path(const KinematicTree& tree,
                                                                               const TreeKinematics& kin,
                                                                               int node_index);

// The matrix [v]x with [v]x w = v x w.
inline Mat3 cross_matrix(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

// Adds the generalized force J_P^T force of a force applied at world point p
// of `node` to `generalized_force` (paper eq. 9).
void add_point_force(const KinematicTree& tree, const TreeKinematics& kin, int node_index,
                     const Vec3& p, const Vec3& force, Coordinates& generalized_force);

}  // namespace rover
