// Kinematic tree of docs/model.md §3 and its recursive kinematics.
#include "core/kinematic_tree.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <Eigen/Geometry>

#include "core/sine_cosine.hpp"

namespace rover {
namespace {

int add_body(KinematicTree& tree, int& body_count, int node_index,
             const RigidBodyParameters& body) {
  const int b = body_count++;
  tree.bodies[b] = body;
  tree.body_node[b] = node_index;
  tree.total_mass_kg += body.mass_kg;
  return b;
}

RigidBodyParameters mirrored(const RigidBodyParameters& body, double s_x, double s_y) {
  RigidBodyParameters m = body;
  m.com_m = mirrored_position(body.com_m, s_x, s_y);
  m.inertia_kgm2 = mirrored_inertia(body.inertia_kgm2, s_x, s_y);
  return m;
}

}  // namespace

KinematicTree build_kinematic_tree(const RoverParameters& p) {
  KinematicTree tree;
  int body_count = 0;
  auto set = [&](int index, int parent, const Vec3& offset, JointType type, const Vec3& axis,
                 int coordinate, double sign) {
    TreeNode& n = tree.nodes[index];
    n.parent = parent;
    n.offset_m = offset;
    n.type = type;
    n.axis = axis;
    n.coordinate = coordinate;
    n.sign = sign;
  };
  const Vec3 ex = Vec3::UnitX(), ey = Vec3::UnitY(), ez = Vec3::UnitZ(), zero = Vec3::Zero();

  // Floating chassis: translations along world axes, then yaw, pitch, roll.
  set(0, -1, zero, JointType::kPrismatic, ex, coord::x, 1.0);
  set(1, 0, zero, JointType::kPrismatic, ey, coord::y, 1.0);
  set(2, 1, zero, JointType::kPrismatic, ez, coord::z, 1.0);
  set(3, 2, zero, JointType::kRevolute, ez, coord::yaw, 1.0);
  set(4, 3, zero, JointType::kRevolute, ey, coord::pitch, 1.0);
  set(node::chassis, 4, zero, JointType::kRevolute, ex, coord::roll, 1.0);
  tree.nodes[node::chassis].body = add_body(tree, body_count, node::chassis, p.chassis);

  // Bogies: phi_R = +phi, phi_L = -phi (massless lever coupling).
  for (const int side : {node::bogie_left, node::bogie_right}) {
    const double s_y = side == node::bogie_left ? 1.0 : -1.0;
    set(side, node::chassis, mirrored_position(p.geometry.bogie_pivot_m, 1.0, s_y),
        JointType::kRevolute, ey, coord::bogie, -s_y);
    tree.nodes[side].body = add_body(tree, body_count, side, mirrored(p.bogie, 1.0, s_y));
  }

  // Legs: hip and knee S-structure joints rotate by Ry(-s_x b), so positive b
  // lifts the wheel; the hub steers about its z axis, the wheel rolls about y.
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const double s_x = leg_sign_x(leg), s_y = leg_sign_y(leg);
    const int bogie = s_y > 0 ? node::bogie_left : node::bogie_right;
    set(node::module1(leg), bogie, mirrored_position(p.geometry.hip_m, s_x, s_y),
        JointType::kRevolute, ey, coord::s_joint(leg, 0), -s_x);
    tree.nodes[node::module1(leg)].body =
        add_body(tree, body_count, node::module1(leg), mirrored(p.module1, s_x, s_y));
    set(node::module2(leg), node::module1(leg), mirrored_position(p.geometry.knee_m, s_x, s_y),
        JointType::kRevolute, ey, coord::s_joint(leg, 1), -s_x);
    tree.nodes[node::module2(leg)].body =
        add_body(tree, body_count, node::module2(leg), mirrored(p.module2, s_x, s_y));
    set(node::hub(leg), node::module2(leg), mirrored_position(p.geometry.wheel_centre_m, s_x, s_y),
        JointType::kRevolute, ez, coord::steer(leg), 1.0);
    set(node::wheel(leg), node::hub(leg), zero, JointType::kRevolute, ey, coord::spin(leg), 1.0);
    tree.nodes[node::wheel(leg)].body =
        add_body(tree, body_count, node::wheel(leg), mirrored(p.wheel, s_x, s_y));
  }
  if (body_count != kNumBodies) throw std::logic_error("kinematic tree: wrong body count");

  for (int i = 0; i < kNumTreeNodes; ++i) {
    int len = 0;
    for (int k = i; k >= 0; k = tree.nodes[k].parent) {
      if (len == kMaxTreeDepth) throw std::logic_error("kinematic tree: too deep");
      tree.path[i][len++] = k;
    }
    tree.path_length[i] = len;
    if (tree.nodes[i].parent >= i) throw std::logic_error("kinematic tree: parents must come first");
    // A coordinate may drive several nodes (the bogie coupling) but never two
    // nodes on one path: that would double-count a partial velocity.
    for (int a = 1; a < len; ++a)
      if (tree.nodes[tree.path[i][a]].coordinate == tree.nodes[i].coordinate)
        throw std::logic_error("kinematic tree: coordinate repeated along a path");
  }
  std::iota(tree.depth_order.begin(), tree.depth_order.end(), 0);
  std::stable_sort(tree.depth_order.begin(), tree.depth_order.end(),
                   [&](int a, int b) { return tree.path_length[a] < tree.path_length[b]; });
  // Coordinate parents; the nodes that share a coordinate must agree on it.
  tree.coordinate_parent.fill(-2);
  for (int i = 0; i < kNumTreeNodes; ++i) {
    const int c = tree.nodes[i].coordinate;
    const int above = tree.path_length[i] > 1 ? tree.nodes[tree.path[i][1]].coordinate : -1;
    if (above >= c) throw std::logic_error("kinematic tree: a coordinate must come after the one above it");
    if (tree.coordinate_parent[c] != -2 && tree.coordinate_parent[c] != above)
      throw std::logic_error("kinematic tree: nodes of one coordinate under different coordinates");
    tree.coordinate_parent[c] = above;
  }
  for (int c = 0; c < kNumCoordinates; ++c)
    if (tree.coordinate_parent[c] == -2) throw std::logic_error("kinematic tree: coordinate drives no node");
  return tree;
}

TreeKinematics forward_kinematics(const KinematicTree& tree, const Coordinates& q,
                                  const Coordinates& u) {
  TreeKinematics kin;
  forward_kinematics(tree, q, u, kin);
  return kin;
}

namespace {

// Index a of the unit axis e_a, or -1 for any other axis.
int elementary_axis(const Vec3& axis) {
  const int a = axis.y() == 1.0 ? 1 : axis.z() == 1.0 ? 2 : axis.x() == 1.0 ? 0 : -1;
  return a >= 0 && axis[(a + 1) % 3] == 0.0 && axis[(a + 2) % 3] == 0.0 ? a : -1;
}

// parent * (rotation by `angle` about e_a of the parent frame): turns the two
// other columns of the parent in their plane.
template <int a>
void rotate_about_unit_axis(const Mat3& parent, double cos_angle, double sin_angle, Mat3& r) {
  constexpr int b = (a + 1) % 3, c = (a + 2) % 3;
  r.col(a) = parent.col(a);
  r.col(b) = cos_angle * parent.col(b) + sin_angle * parent.col(c);
  r.col(c) = cos_angle * parent.col(c) - sin_angle * parent.col(b);
}

// parent * (rotation by `angle` about the unit `axis`), with the angle's
// cosine and sine; `elementary` is elementary_axis(axis). The tree's rotations
// are all elementary; any other axis goes through Eigen::AngleAxis.
void rotate_about(const Mat3& parent, const Vec3& axis, int elementary, double angle, double cos_angle,
                  double sin_angle, Mat3& r) {
  switch (elementary) {
    case 0: return rotate_about_unit_axis<0>(parent, cos_angle, sin_angle, r);
    case 1: return rotate_about_unit_axis<1>(parent, cos_angle, sin_angle, r);
    case 2: return rotate_about_unit_axis<2>(parent, cos_angle, sin_angle, r);
    default: r = parent * Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  }
}

// R I R^T for a symmetric I, column by column (which the compiler vectorizes,
// unlike the 3 x 3 product R * I), then mirrored: exactly symmetric.
void rotate_inertia(const Mat3& rotation, const Mat3& inertia, Mat3& world) {
  Mat3 rotated;  // R I
  for (int c = 0; c < 3; ++c)
    rotated.col(c) = rotation.col(0) * inertia(0, c) + rotation.col(1) * inertia(1, c) +
                     rotation.col(2) * inertia(2, c);
  for (int c = 0; c < 3; ++c)
    world.col(c) = rotated.col(0) * rotation(c, 0) + rotated.col(1) * rotation(c, 1) +
                   rotated.col(2) * rotation(c, 2);
  world(0, 1) = world(1, 0);
  world(0, 2) = world(2, 0);
  world(1, 2) = world(2, 1);
}

// The recursion of forward_kinematics(); with kPoseAndVelocityOnly, only the
// rotation, origin, axis, omega and velocity of the nodes.
template <bool kPoseAndVelocityOnly>
void node_kinematics(const KinematicTree& tree, const Coordinates& q, const Coordinates& u,
                     TreeKinematics& kin) {
  constexpr bool kFull = !kPoseAndVelocityOnly;
  // Every node's displacement, and its sine and cosine at once (a
  // prismatic node's are not used).
  std::array<double, kNumTreeNodes> displacements;
  for (int i = 0; i < kNumTreeNodes; ++i) displacements[i] = tree.nodes[i].sign * q[tree.nodes[i].coordinate];
  SinesCosines<kNumTreeNodes> trig;
  sines_and_cosines(displacements, trig);
  for (int i = 0; i < kNumTreeNodes; ++i) {
    const TreeNode& node = tree.nodes[i];
    NodeKinematics& k = kin.nodes[i];
    const double displacement = displacements[i];
    const double rate = node.sign * u[node.coordinate];
    const int elementary = elementary_axis(node.axis);
    const bool revolute = node.type == JointType::kRevolute;
    if (node.parent < 0) {
      // Under the world frame (at rest, world axes) every parent term vanishes.
      k.axis = node.axis;
      k.origin = node.offset_m;
      if constexpr (kFull) {
        k.alpha_bias.setZero();
        k.accel_bias.setZero();
      }
      if (revolute) {
        rotate_about(Mat3::Identity(), node.axis, elementary, displacement, trig.cos[i], trig.sin[i], k.rotation);
        k.omega = k.axis * rate;
        k.velocity.setZero();
      } else {
        k.rotation.setIdentity();
        k.origin += k.axis * displacement;
        k.omega.setZero();
        k.velocity = k.axis * rate;
      }
    } else {
      const NodeKinematics& parent = kin.nodes[node.parent];
      if (elementary >= 0)
        k.axis = parent.rotation.col(elementary);
      else
        k.axis = parent.rotation * node.axis;
      // r: node origin relative to the parent origin. A joint at the parent
      // origin (r = 0) inherits the origin's velocity and bias acceleration.
      const bool at_parent_origin = (node.offset_m.array() == 0.0).all();
      if (revolute) {
        const Vec3 spin = k.axis * rate;
        rotate_about(parent.rotation, node.axis, elementary, displacement, trig.cos[i], trig.sin[i], k.rotation);
        k.omega = parent.omega + spin;
        if constexpr (kFull) k.alpha_bias = parent.alpha_bias + parent.omega.cross(spin);
        if (at_parent_origin) {
          k.origin = parent.origin;
          k.velocity = parent.velocity;
          if constexpr (kFull) k.accel_bias = parent.accel_bias;
        } else {
          const Vec3 r = parent.rotation * node.offset_m;
          const Vec3 omega_cross_r = parent.omega.cross(r);
          k.origin = parent.origin + r;
          k.velocity = parent.velocity + omega_cross_r;
          if constexpr (kFull)
            k.accel_bias = parent.accel_bias + parent.alpha_bias.cross(r) + parent.omega.cross(omega_cross_r);
        }
      } else {
        Vec3 r = k.axis * displacement;
        if (!at_parent_origin) r += parent.rotation * node.offset_m;
        const Vec3 slide = k.axis * rate;
        const Vec3 omega_cross_r = parent.omega.cross(r);
        k.rotation = parent.rotation;
        k.omega = parent.omega;
        k.origin = parent.origin + r;
        k.velocity = parent.velocity + omega_cross_r + slide;
        if constexpr (kFull) {
          k.alpha_bias = parent.alpha_bias;
          k.accel_bias = parent.accel_bias + parent.alpha_bias.cross(r) +
                         parent.omega.cross(omega_cross_r) + 2.0 * parent.omega.cross(slide);
        }
      }
    }
    if (kFull && node.body >= 0) {
      const RigidBodyParameters& body = tree.bodies[node.body];
      BodyKinematics& b = kin.bodies[node.body];
      b.com_offset = k.rotation * body.com_m;
      rotate_inertia(k.rotation, body.inertia_kgm2, b.inertia);
    }
  }
  kin.reference = kin.nodes[node::chassis].origin;
}

}  // namespace

void forward_pose_and_velocity(const KinematicTree& tree, const Coordinates& q, const Coordinates& u,
                               TreeKinematics& kin) {
  node_kinematics<true>(tree, q, u, kin);
}

void forward_kinematics(const KinematicTree& tree, const Coordinates& q, const Coordinates& u,
                        TreeKinematics& kin) {
  node_kinematics<false>(tree, q, u, kin);
  for (int i = 0; i < kNumTreeNodes; ++i) {
    NodeKinematics& k = kin.nodes[i];
    const double s = tree.nodes[i].sign;
    if (tree.nodes[i].type == JointType::kRevolute) {
      k.motion_omega = s * k.axis;
      k.motion_velocity = k.motion_omega.cross(kin.reference - k.origin);
    } else {
      k.motion_omega.setZero();
      k.motion_velocity = s * k.axis;
    }
  }
}

namespace {

// A path Jacobian spread into the columns of a 3 x 23 one.
Eigen::Matrix<double, 3, kNumCoordinates> on_columns(const KinematicTree& tree, int node_index,
                                                     const PathJacobian& rows) {
  Eigen::Matrix<double, 3, kNumCoordinates> jacobian = Eigen::Matrix<double, 3, kNumCoordinates>::Zero();
  for (int a = 0; a < tree.path_length[node_index]; ++a)
    jacobian.col(tree.nodes[tree.path[node_index][a]].coordinate) = rows.row(a).transpose();
  return jacobian;
}

}  // namespace

PathJacobian point_jacobian_on_path(const KinematicTree& tree, const TreeKinematics& kin, int node_index,
                                    const Vec3& p) {
  PathJacobian rows = PathJacobian::Zero();
  const Vec3 lever = p - kin.reference;
  for (int a = 0; a < tree.path_length[node_index]; ++a) {
    const NodeKinematics& n = kin.nodes[tree.path[node_index][a]];
    rows.row(a) += (n.motion_velocity + n.motion_omega.cross(lever)).transpose();
  }
  return rows;
}

Eigen::Matrix<double, 3, kNumCoordinates> point_jacobian(const KinematicTree& tree,
                                                         const TreeKinematics& kin,
                                                         int node_index, const Vec3& p) {
  return on_columns(tree, node_index, point_jacobian_on_path(tree, kin, node_index, p));
}

PathJacobian angular_jacobian_on_path(const KinematicTree& tree, const TreeKinematics& kin, int node_index) {
  PathJacobian rows = PathJacobian::Zero();
  for (int a = 0; a < tree.path_length[node_index]; ++a)
    rows.row(a) += kin.nodes[tree.path[node_index][a]].motion_omega.transpose();
  return rows;
}

Eigen::Matrix<double, 3, kNumCoordinates> angular_jacobian(const KinematicTree& tree,
                                                           const TreeKinematics& kin, int node_index) {
  return on_columns(tree, node_index, angular_jacobian_on_path(tree, kin, node_index));
}

FrameVelocityPositionDerivativeOnPath frame_velocity_position_derivative_on_path(const KinematicTree& tree,
                                                                               const TreeKinematics& kin,
                                                                               int node_index) {
  // d v_o / dq is formed column by column and then turned into path rows:
  // the compiler then fuses its multiply-adds as in the 3 x 23 form (the
  // same bits).
  using PathColumns = Eigen::Matrix<double, 3, kMaxTreeDepth>;
  const NodeKinematics& frame = kin.nodes[node_index];
  PathColumns d_origin_velocity = PathColumns::Zero();
  PathJacobian d_omega = PathJacobian::Zero();
  for (int a = 0; a < tree.path_length[node_index]; ++a) {
    const int k = tree.path[node_index][a];
    const NodeKinematics& joint = kin.nodes[k];
    if (tree.nodes[k].type == JointType::kRevolute) {
      const Vec3& w = joint.motion_omega;
      const Vec3 r = frame.origin - joint.origin;
      d_origin_velocity.col(a) += w.cross(frame.velocity - joint.velocity - joint.omega.cross(r)) +
                                  joint.omega.cross(w.cross(r));
      d_omega.row(a) += w.cross(frame.omega - joint.omega).transpose();
    } else {
      d_origin_velocity.col(a) += joint.omega.cross(joint.motion_velocity);
    }
  }
  return {d_origin_velocity.transpose(), d_omega};
}

FrameVelocityPositionDerivative frame_velocity_position_derivative(const KinematicTree& tree,
                                                                   const TreeKinematics& kin,
                                                                   int node_index) {
  const FrameVelocityPositionDerivativeOnPath d = frame_velocity_position_derivative_on_path(tree, kin, node_index);
  return {on_columns(tree, node_index, d.d_origin_velocity), on_columns(tree, node_index, d.d_omega)};
}

void add_point_force(const KinematicTree& tree, const TreeKinematics& kin, int node_index,
                     const Vec3& p, const Vec3& force, Coordinates& generalized_force) {
  const Vec3 moment = (p - kin.reference).cross(force);  // about the reference point
  for (int a = 0; a < tree.path_length[node_index]; ++a) {
    const int k = tree.path[node_index][a];
    const NodeKinematics& n = kin.nodes[k];
    generalized_force[tree.nodes[k].coordinate] +=
        n.motion_omega.dot(moment) + n.motion_velocity.dot(force);
  }
}

}  // namespace rover
