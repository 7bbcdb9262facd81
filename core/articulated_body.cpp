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

Mat3 cross_matrix(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

// A body's spatial inertia about the reference point, in the convention of
// mass_matrix(): momentum = (I_ref w + h x v, m v + w x h), h = m (c - ref).
Matrix6 spatial_inertia(double mass, const Mat3& inertia_com, const Vec3& com_from_reference) {
  const Mat3 h = cross_matrix(mass * com_from_reference);
  Matrix6 I;
  I.topLeftCorner<3, 3>() = inertia_about_offset(mass, inertia_com, com_from_reference);
  I.topRightCorner<3, 3>() = h;
  I.bottomLeftCorner<3, 3>() = h.transpose();
  I.bottomRightCorner<3, 3>() = mass * Mat3::Identity();
  return I;
}

}  // namespace

std::optional<Coordinates> articulated_body_solve(const KinematicTree& tree, const TreeKinematics& kin,
                                                  const Coordinates& tau) {
  std::array<Matrix6, kNumTreeNodes> inertia;  // I^A of each node's subtree
  std::array<Vector6, kNumTreeNodes> bias;     // p^A
  std::array<bool, kNumTreeNodes> loaded{};    // whether I^A, p^A carry anything
  std::array<Vector6, kNumTreeNodes> motion;   // S_i
  for (int i = 0; i < kNumTreeNodes; ++i) {
    const NodeKinematics& n = kin.nodes[i];
    motion[i] << n.motion_omega, n.motion_velocity;
    const int b = tree.nodes[i].body;
    if (b >= 0) {
      const BodyKinematics& body = kin.bodies[b];
      inertia[i] = spatial_inertia(tree.bodies[b].mass_kg, body.inertia, n.origin + body.com_offset - kin.reference);
      loaded[i] = true;
    } else {
      inertia[i].setZero();
    }
    bias[i].setZero();
  }

  // Pass 2 over the legs, leaves first (children come after their parents).
  std::array<Vector6, kNumTreeNodes> U;
  std::array<double, kNumTreeNodes> D{}, u{};
  for (int i = kNumTreeNodes - 1; i >= 0; --i) {
    const int c = tree.nodes[i].coordinate;
    if (c < kTrunk) continue;
    U[i].noalias() = inertia[i] * motion[i];
    D[i] = motion[i].dot(U[i]);
    if (!(D[i] > 0.0) || !std::isfinite(D[i])) return std::nullopt;
    u[i] = tau[c] - motion[i].dot(bias[i]);
    const int p = tree.nodes[i].parent;
    const double inverse = 1.0 / D[i];
    const Vector6 scaled = inverse * U[i];
    for (int col = 0; col < 6; ++col) inertia[p].col(col) += inertia[i].col(col) - U[i][col] * scaled;
    bias[p] += bias[i] + (u[i] * inverse) * U[i];
    loaded[p] = true;
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
    if (ci >= kTrunk || !loaded[i]) continue;
    const Vector6 momentum = inertia[i] * motion[i];
    rhs[ci] -= motion[i].dot(bias[i]);
    A(ci, ci) += motion[i].dot(momentum);
    for (int k = 1; k < tree.path_length[i]; ++k) {
      const int j = tree.path[i][k];
      const int cj = tree.nodes[j].coordinate;
      A(ci, cj) += motion[j].dot(momentum);
    }
    const int p = tree.nodes[i].parent;
    if (p >= 0) {
      inertia[p] += inertia[i];
      bias[p] += bias[i];
      loaded[p] = true;
    }
  }
  FixedSizeLLT<kTrunk> trunk;
  if (!trunk.compute(A)) return std::nullopt;
  TrunkVector trunk_acceleration = rhs;
  trunk.solve_in_place(trunk_acceleration);

  // Pass 3 over the legs, root first.
  Coordinates a;
  a.head<kTrunk>() = trunk_acceleration;
  std::array<Vector6, kNumTreeNodes> acceleration;
  for (int i = 0; i < kNumTreeNodes; ++i) {
    const int c = tree.nodes[i].coordinate;
    const int p = tree.nodes[i].parent;
    const Vector6 above = p >= 0 ? acceleration[p] : Vector6::Zero();
    if (c >= kTrunk) a[c] = (u[i] - U[i].dot(above)) / D[i];
    acceleration[i] = above + a[c] * motion[i];
  }
  if (!a.allFinite()) return std::nullopt;
  return a;
}

}  // namespace rover
