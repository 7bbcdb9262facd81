// The articulated-body solve of M(q) a = tau (see articulated_body.hpp).
#include "core/articulated_body.hpp"

#include <array>
#include <cmath>

#include "core/dynamics.hpp"
#include "core/fixed_size_llt.hpp"

namespace rover {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;  // (angular; linear) about the reference point
// A 6 x 6 spatial inertia, and its products with unit motions, are stored with
// two zero rows below the six, so that a column is one packet of eight
// doubles (AVX-512) or two of four (AVX) instead of three of two: the column
// operations below then take a third of the instructions, each entry the same
// arithmetic (the zero rows stay zero). Inner products read the first six rows.
constexpr int kPaddedRows = 8;
using PaddedColumn = Eigen::Matrix<double, kPaddedRows, 1>;
using PaddedInertia = Eigen::Matrix<double, kPaddedRows, 6>;

// The coordinates above the legs: x, y, z, theta, chi, psi and phi.
constexpr int kTrunk = coord::bogie + 1;
using TrunkVector = Eigen::Matrix<double, kTrunk, 1>;
using TrunkMatrix = Eigen::Matrix<double, kTrunk, kTrunk>;

// A body's spatial inertia about the reference point, in the convention of
// mass_matrix(): momentum = (I_ref w + h x v, m v + w x h), h = m (c - ref),
// written into `I`.
void set_spatial_inertia(double mass, const Mat3& inertia_com, const Vec3& com_from_reference, PaddedInertia& I) {
  const Vec3 h = mass * com_from_reference;
  set_inertia_about_offset(mass, inertia_com, com_from_reference, I.topLeftCorner<3, 3>());
  I.block<3, 3>(3, 3) = mass * Mat3::Identity();
  I.bottomRows<kPaddedRows - 6>().setZero();
  // [h]x above the diagonal and its transpose below, entry by entry.
  for (int c = 0; c < 3; ++c) I(c, 3 + c) = I(3 + c, c) = 0.0;
  I(0, 4) = I(4, 0) = -h.z();
  I(0, 5) = I(5, 0) = h.y();
  I(1, 3) = I(3, 1) = h.z();
  I(1, 5) = I(5, 1) = -h.x();
  I(2, 3) = I(3, 2) = -h.y();
  I(2, 4) = I(4, 2) = h.x();
}

// The articulated inertia and bias of every node's subtree, filled as the
// passes reach them: a node holds nothing until its body or a child's
// contribution arrives, and the first arrival is assigned, not added.
struct Subtrees {
  std::array<PaddedInertia, kNumTreeNodes> inertia;  // I^A
  std::array<Vector6, kNumTreeNodes> bias;     // p^A
  std::array<bool, kNumTreeNodes> loaded{};

  void add(int node, const PaddedInertia& child_inertia, const Vector6& child_bias) {
    if (loaded[node]) {
      inertia[node] += child_inertia;
      bias[node] += child_bias;
    } else {
      inertia[node] = child_inertia;
      bias[node] = child_bias;
      loaded[node] = true;
    }
  }
};

// The state of one recursion, filled by its passes: the unit motions S_i, the
// legs' U_i, D_i and u_i, the trunk matrix A and, for each trunk node,
// S_i^T p^A_i (subtracted from tau in node order once tau is complete).
struct Recursion {
  Subtrees sub;
  std::array<Vector6, kNumTreeNodes> motion;
  std::array<PaddedColumn, kNumTreeNodes> U;
  std::array<double, kNumTreeNodes> D, u;     // written by pass 2 before pass 3 reads them
  std::array<double, kNumTreeNodes> trunk_bias;  // written by add_trunk_node() for loaded trunk nodes
  TrunkMatrix A = TrunkMatrix::Zero();
};

// Node i's body, if it has one, as the articulated inertia its subtree
// starts from (with no bias), and its unit motion S_i.
void start_node(const KinematicTree& tree, const TreeKinematics& kin, int i, Recursion& r) {
  const NodeKinematics& n = kin.nodes[i];
  r.motion[i] << n.motion_omega, n.motion_velocity;
  const int b = tree.nodes[i].body;
  if (b < 0) return;
  const BodyKinematics& body = kin.bodies[b];
  set_spatial_inertia(tree.bodies[b].mass_kg, body.inertia, n.origin + body.com_offset - kin.reference,
                      r.sub.inertia[i]);
  r.sub.bias[i].setZero();
  r.sub.loaded[i] = true;
}

// Pass 2 at leg node i, whose subtree is complete, with tau_i = `tau`: U_i,
// D_i, u_i, and I^A_i - U_i U_i^T / D_i and p^A_i + U_i u_i / D_i to the
// parent. False for a massless subtree or a pivot that is not positive.
bool eliminate_leg_joint(const KinematicTree& tree, int i, double tau, Recursion& r) {
  Subtrees& sub = r.sub;
  if (!sub.loaded[i]) return false;  // a massless subtree
  const Vector6& motion = r.motion[i];
  r.U[i].noalias() = sub.inertia[i] * motion;
  const double D = motion.dot(r.U[i].head<6>());
  r.D[i] = D;
  if (!(D > 0.0) || !std::isfinite(D)) return false;
  r.u[i] = tau - motion.dot(sub.bias[i]);
  const double inverse = 1.0 / D;
  const PaddedColumn scaled = inverse * r.U[i];
  // I^A_i - U_i U_i^T / D_i to the parent, column by column (one axpy each).
  const int p = tree.nodes[i].parent;
  PaddedInertia& parent = sub.inertia[p];
  if (sub.loaded[p]) {
    for (int col = 0; col < 6; ++col) parent.col(col) += sub.inertia[i].col(col) - r.U[i][col] * scaled;
    sub.bias[p] += sub.bias[i] + r.u[i] * scaled.head<6>();
  } else {
    for (int col = 0; col < 6; ++col) parent.col(col) = sub.inertia[i].col(col) - r.U[i][col] * scaled;
    sub.bias[p] = sub.bias[i] + r.u[i] * scaled.head<6>();
    sub.loaded[p] = true;
  }
  return true;
}

// The trunk, as the composite-rigid-body algorithm forms a mass matrix
// (dynamics.cpp): trunk node i carries the articulated inertia of its
// subtree, children added before it is reached; A(c_i, c_j) = S_j^T I^C_i S_i
// for every trunk node j on node i's path (c_j < c_i: the lower triangle, all
// that FixedSizeLLT reads). The two nodes of phi add into its row and column.
void add_trunk_node(const KinematicTree& tree, int i, Recursion& r) {
  Subtrees& sub = r.sub;
  if (!sub.loaded[i]) return;
  const int ci = tree.nodes[i].coordinate;
  const PaddedColumn momentum = sub.inertia[i] * r.motion[i];
  r.trunk_bias[i] = r.motion[i].dot(sub.bias[i]);
  r.A(ci, ci) += r.motion[i].dot(momentum.head<6>());
  for (int k = 1; k < tree.path_length[i]; ++k) {
    const int j = tree.path[i][k];
    r.A(ci, tree.nodes[j].coordinate) += r.motion[j].dot(momentum.head<6>());
  }
  const int p = tree.nodes[i].parent;
  if (p >= 0) sub.add(p, sub.inertia[i], sub.bias[i]);
}

// With every node passed, and tau complete: the trunk's 7 x 7 solve, then
// pass 3 over the legs, root first: the acceleration of each node's frame
// (the sum of S_j a_j over its path), then the legs' joint accelerations.
bool solve_trunk_and_legs(const KinematicTree& tree, const Coordinates& tau, Recursion& r, Coordinates& a) {
  TrunkVector rhs = tau.head<kTrunk>();
  for (int i = kNumTreeNodes - 1; i >= 0; --i) {
    const int ci = tree.nodes[i].coordinate;
    if (ci < kTrunk && r.sub.loaded[i]) rhs[ci] -= r.trunk_bias[i];
  }
  FixedSizeLLT<kTrunk> trunk;
  if (!trunk.compute(r.A)) return false;
  trunk.solve_in_place(rhs);
  a.head<kTrunk>() = rhs;
  std::array<Vector6, kNumTreeNodes> acceleration;
  for (const int i : tree.depth_order) {
    const int c = tree.nodes[i].coordinate;
    const int p = tree.nodes[i].parent;
    if (p < 0) {  // a root: at rest above it
      if (c >= kTrunk) a[c] = r.u[i] / r.D[i];
      acceleration[i] = a[c] * r.motion[i];
      continue;
    }
    const Vector6& above = acceleration[p];
    if (c >= kTrunk) a[c] = (r.u[i] - r.U[i].head<6>().dot(above)) / r.D[i];
    acceleration[i] = above + a[c] * r.motion[i];
  }
  return a.allFinite();
}

}  // namespace

// Both entry points are flattened: the helpers above are inlined into their
// loops, whose state then stays in registers between them.
[[gnu::flatten]] std::optional<Coordinates> articulated_body_solve(const KinematicTree& tree, const TreeKinematics& kin,
                                                  const Coordinates& tau) {
  Recursion r;
  for (int i = 0; i < kNumTreeNodes; ++i) start_node(tree, kin, i, r);
  // Leaves first (the reverse of the depth order): the legs' pass 2, the trunk's composites.
  for (int k = kNumTreeNodes - 1; k >= 0; --k) {
    const int i = tree.depth_order[k];
    const int c = tree.nodes[i].coordinate;
    if (c < kTrunk) {
      add_trunk_node(tree, i, r);
    } else if (!eliminate_leg_joint(tree, i, tau[c], r)) {
      return std::nullopt;
    }
  }
  std::optional<Coordinates> result(std::in_place);
  if (!solve_trunk_and_legs(tree, tau, r, *result)) return std::nullopt;
  return result;
}

[[gnu::flatten]] bool articulated_forcing_and_solve(const KinematicTree& tree, const TreeKinematics& kin,
                                                    double gravity_mps2, const Coordinates& joint_forces,
                                                    const Coordinates& contact_forces,
                                                    Coordinates& forcing_without_contact, Coordinates& forcing,
                                                    Coordinates& acceleration) {
  Recursion r;
  for (int i = 0; i < kNumTreeNodes; ++i) start_node(tree, kin, i, r);
  ForcingPass pass(tree, kin, gravity_mps2);
  const auto complete = [&](int c) {
    pass.complete(c, joint_forces, contact_forces, forcing_without_contact, forcing);
  };
  for (int k = kNumTreeNodes - 1; k >= 0; --k) {
    const int i = tree.depth_order[k];
    pass.visit(i);
    const int c = tree.nodes[i].coordinate;
    if (c < kTrunk) {
      add_trunk_node(tree, i, r);
      continue;
    }
    complete(c);  // a leg coordinate drives this node alone
    if (!eliminate_leg_joint(tree, i, forcing[c], r)) return false;
  }
  for (int c = 0; c < kTrunk; ++c) complete(c);
  return solve_trunk_and_legs(tree, forcing, r, acceleration);
}

}  // namespace rover
