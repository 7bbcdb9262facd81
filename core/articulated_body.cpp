// The articulated-body solve of M(q) a = tau (see articulated_body.hpp).
#include "core/articulated_body.hpp"

#include <array>
#include <cmath>

#include "core/dynamics.hpp"
#include "core/fixed_size_llt.hpp"

namespace rover {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;  // (angular; linear) about the reference point
using Matrix6 = Eigen::Matrix<double, 6, 6>;

// The coordinates above the legs: x, y, z, theta, chi, psi and phi.
constexpr int kTrunk = coord::bogie + 1;
using TrunkVector = Eigen::Matrix<double, kTrunk, 1>;
using TrunkMatrix = Eigen::Matrix<double, kTrunk, kTrunk>;

// A body's spatial inertia about the reference point, in the convention of
// mass_matrix(): momentum = (I_ref w + h x v, m v + w x h), h = m (c - ref),
// written into `I`.
void set_spatial_inertia(double mass, const Mat3& inertia_com, const Vec3& com_from_reference, Matrix6& I) {
  const Vec3 h = mass * com_from_reference;
  set_inertia_about_offset(mass, inertia_com, com_from_reference, I.topLeftCorner<3, 3>());
  I.bottomRightCorner<3, 3>() = mass * Mat3::Identity();
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
  std::array<Matrix6, kNumTreeNodes> inertia;  // I^A
  std::array<Vector6, kNumTreeNodes> bias;     // p^A
  std::array<bool, kNumTreeNodes> loaded{};

  void add(int node, const Matrix6& child_inertia, const Vector6& child_bias) {
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

}  // namespace

std::optional<Coordinates> articulated_body_solve(const KinematicTree& tree, const TreeKinematics& kin,
                                                  const Coordinates& tau) {
  Subtrees sub;
  for (int b = 0; b < kNumBodies; ++b) {
    const int i = tree.body_node[b];
    const BodyKinematics& body = kin.bodies[b];
    set_spatial_inertia(tree.bodies[b].mass_kg, body.inertia,
                        kin.nodes[i].origin + body.com_offset - kin.reference, sub.inertia[i]);
    sub.bias[i].setZero();
    sub.loaded[i] = true;
  }
  std::array<Vector6, kNumTreeNodes> motion;  // S_i
  for (int i = 0; i < kNumTreeNodes; ++i) motion[i] << kin.nodes[i].motion_omega, kin.nodes[i].motion_velocity;

  // Pass 2 over the legs, leaves first (children come after their parents).
  std::array<Vector6, kNumTreeNodes> U;
  std::array<double, kNumTreeNodes> D{}, u{};
  for (int i = kNumTreeNodes - 1; i >= 0; --i) {
    const int c = tree.nodes[i].coordinate;
    if (c < kTrunk) continue;
    if (!sub.loaded[i]) return std::nullopt;  // a massless subtree
    U[i].noalias() = sub.inertia[i] * motion[i];
    D[i] = motion[i].dot(U[i]);
    if (!(D[i] > 0.0) || !std::isfinite(D[i])) return std::nullopt;
    u[i] = tau[c] - motion[i].dot(sub.bias[i]);
    const double inverse = 1.0 / D[i];
    const Vector6 scaled = inverse * U[i];
    // I^A_i - U_i U_i^T / D_i to the parent, column by column (one axpy each).
    const int p = tree.nodes[i].parent;
    Matrix6& parent = sub.inertia[p];
    if (sub.loaded[p]) {
      for (int col = 0; col < 6; ++col) parent.col(col) += sub.inertia[i].col(col) - U[i][col] * scaled;
      sub.bias[p] += sub.bias[i] + u[i] * scaled;
    } else {
      for (int col = 0; col < 6; ++col) parent.col(col) = sub.inertia[i].col(col) - U[i][col] * scaled;
      sub.bias[p] = sub.bias[i] + u[i] * scaled;
      sub.loaded[p] = true;
    }
  }

  // The trunk, as the composite-rigid-body algorithm forms a mass matrix
  // (dynamics.cpp): each trunk node carries the articulated inertia of its
  // subtree, children added before their parent is reached; A(c_i, c_j) =
  // S_j^T I^C_i S_i for every trunk node j on node i's path (c_j < c_i: the
  // lower triangle, all that FixedSizeLLT reads). The two nodes of phi add
  // into its row and column.
  TrunkMatrix A = TrunkMatrix::Zero();
  TrunkVector rhs = tau.head<kTrunk>();
  for (int i = kNumTreeNodes - 1; i >= 0; --i) {
    const int ci = tree.nodes[i].coordinate;
    if (ci >= kTrunk || !sub.loaded[i]) continue;
    const Vector6 momentum = sub.inertia[i] * motion[i];
    rhs[ci] -= motion[i].dot(sub.bias[i]);
    A(ci, ci) += motion[i].dot(momentum);
    for (int k = 1; k < tree.path_length[i]; ++k) {
      const int j = tree.path[i][k];
      A(ci, tree.nodes[j].coordinate) += motion[j].dot(momentum);
    }
    const int p = tree.nodes[i].parent;
    if (p >= 0) sub.add(p, sub.inertia[i], sub.bias[i]);
  }
  FixedSizeLLT<kTrunk> trunk;
  if (!trunk.compute(A)) return std::nullopt;
  trunk.solve_in_place(rhs);

  // Pass 3 over the legs, root first: the acceleration of each node's frame
  // (the sum of S_j a_j over its path), then the legs' joint accelerations.
  std::optional<Coordinates> result(std::in_place);
  Coordinates& a = *result;
  a.head<kTrunk>() = rhs;
  std::array<Vector6, kNumTreeNodes> acceleration;
  for (int i = 0; i < kNumTreeNodes; ++i) {
    const int c = tree.nodes[i].coordinate;
    const int p = tree.nodes[i].parent;
    if (p < 0) {  // a root: at rest above it
      if (c >= kTrunk) a[c] = u[i] / D[i];
      acceleration[i] = a[c] * motion[i];
      continue;
    }
    const Vector6& above = acceleration[p];
    if (c >= kTrunk) a[c] = (u[i] - U[i].dot(above)) / D[i];
    acceleration[i] = above + a[c] * motion[i];
  }
  if (!a.allFinite()) return std::nullopt;
  return result;
}

}  // namespace rover
