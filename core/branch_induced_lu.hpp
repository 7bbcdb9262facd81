// Factorizations of the 23 x 23 matrices of the SA model that exploit their
// branch-induced sparsity (R. Featherstone, "Efficient factorization of the
// joint-space inertia matrix for branched kinematic trees", IJRR 24 (2005)
// 487-500): the mass matrix M(q) of the right-hand side (docs/model.md §4)
// and the iteration matrix M0 - h g D - h^2 g^2 K of the stiff integrator
// (§9).
//
// The coordinates form a tree (KinematicTree::coordinate_parent): a trunk of
// seven, the floating base (x, y, z, theta, chi, psi) and the bogie phi, each
// above the next, carrying four legs of four coordinates each (hip and knee
// S-joints, steering, rolling), each above the next. Entry (i, j) of M is
// non-zero only if one of i, j is an ancestor of the other (a joint moves only
// the bodies below it), and so is every entry of the stiff force Jacobians D
// and K (a contact force acts on the joints above its wheel and depends on
// them only). With the trunk t and leg l blocks
//     A = [ A_tt  A_t1 ... A_t4 ]
//         [ A_1t  A_11          ]      (the leg blocks do not couple)
//         [ ...         ...     ]
//         [ A_4t            A_44]
// eliminating the legs first (Featherstone's leaves-first order) creates no
// fill-in: the trunk's Schur complement S = A_tt - sum_l A_tl A_ll^{-1} A_lt
// is the only new matrix. The work is four 4 x 4 factorizations, one 7 x 7,
// and small fixed-size products, which Eigen unrolls and vectorizes: about
// three times less than a dense 23 x 23 LU with partial pivoting, and less
// than a dense Cholesky for M.
//
// The blocks are factorized by LU with partial pivoting, for M (symmetric
// positive definite) as for the iteration matrix (not symmetric), with
// fixed_size_lu.hpp, whose loops the compiler unrolls at these sizes (Eigen's
// PartialPivLU and its triangular solves run through kernels for run-time
// sizes, which cost three times as much here). A matrix with an entry
// coupling two legs, or a block that is singular, falls back to a dense LU
// with partial pivoting of the whole matrix, so solve() is always valid.
#pragma once

#include <array>
#include <bit>
#include <cstdint>

#include <Eigen/Core>
#include <Eigen/LU>

#include "core/coordinates.hpp"
#include "core/fixed_size_lu.hpp"
#include "core/rover_parameters.hpp"

namespace rover {

// Whether the entries of `a` at the positions `entries` (in its column-major
// storage) are all zero (+0 or -0; a NaN is not), by or-ing the bits of their
// magnitudes: one pass without a branch per entry.
template <std::size_t Count>
bool entries_all_zero(const CoordinateMatrix& a, const std::array<int, Count>& entries) {
  constexpr std::uint64_t kMagnitude = ~(std::uint64_t{1} << 63);
  std::uint64_t bits = 0;
  for (const int e : entries) bits |= std::bit_cast<std::uint64_t>(a.data()[e]) & kMagnitude;
  return bits == 0;
}

class BranchInducedLU {
 public:
  static constexpr int kTrunk = coord::bogie + 1;  // x .. psi, phi
  static constexpr int kLeg = 4;                   // hip, knee, steering, rolling
  using Matrix = CoordinateMatrix;
  using Vector = Coordinates;

  // The coordinates of leg l, from the top down.
  static constexpr std::array<int, kLeg> leg_coordinates(int leg) {
    return {coord::s_joint(leg, 0), coord::s_joint(leg, 1), coord::steer(leg), coord::spin(leg)};
  }

  // The entries of v at the coordinates of leg l, from the top down.
  static Eigen::Matrix<double, kLeg, 1> gather(const Vector& v, int leg) {
    const std::array<int, kLeg> c = leg_coordinates(leg);
    return Eigen::Matrix<double, kLeg, 1>(v[c[0]], v[c[1]], v[c[2]], v[c[3]]);
  }

  // Returns true if the block elimination was used, false if the dense
  // fallback was.
  bool compute(const Matrix& a) {
    dense_ = !legs_uncoupled(a) || !eliminate(a);
    if (dense_) dense_lu_.compute(a);
    return !dense_;
  }

  Vector solve(const Vector& b) const {
    if (dense_) return dense_lu_.solve(b);
    Vector x;
    TrunkVector rhs = b.head<kTrunk>();
    std::array<LegVector, kNumLegs> y;
    for (int l = 0; l < kNumLegs; ++l) {
      y[l] = gather(b, l);
      leg_lu_[l].solve_in_place(y[l]);
      rhs.noalias() -= trunk_leg_[l] * y[l];
    }
    TrunkVector x_trunk = rhs;
    trunk_lu_.solve_in_place(x_trunk);
    x.head<kTrunk>() = x_trunk;
    for (int l = 0; l < kNumLegs; ++l) {
      const LegVector x_leg = y[l] - leg_trunk_solved_[l] * x_trunk;
      const std::array<int, kLeg> c = leg_coordinates(l);
      for (int i = 0; i < kLeg; ++i) x[c[i]] = x_leg[i];
    }
    return x;
  }

  // Column by column, for a matrix right-hand side.
  template <typename Derived>
  Eigen::Matrix<double, kNumCoordinates, Derived::ColsAtCompileTime> solve(
      const Eigen::MatrixBase<Derived>& b) const {
    Eigen::Matrix<double, kNumCoordinates, Derived::ColsAtCompileTime> x(kNumCoordinates, b.cols());
    for (Eigen::Index c = 0; c < b.cols(); ++c) x.col(c) = solve(Vector(b.col(c)));
    return x;
  }

  bool used_dense_fallback() const { return dense_; }

 private:
  using TrunkVector = Eigen::Matrix<double, kTrunk, 1>;
  using TrunkMatrix = Eigen::Matrix<double, kTrunk, kTrunk>;
  using LegVector = Eigen::Matrix<double, kLeg, 1>;
  using LegMatrix = Eigen::Matrix<double, kLeg, kLeg>;
  using LegTrunk = Eigen::Matrix<double, kLeg, kTrunk>;
  using TrunkLeg = Eigen::Matrix<double, kTrunk, kLeg>;


  // The positions, in the column-major storage of a 23 x 23 matrix, of its
  // entries that couple two different legs.
  static constexpr int kNumCouplingEntries = kLeg * kLeg * kNumLegs * (kNumLegs - 1);
  static constexpr std::array<int, kNumCouplingEntries> coupling_entries() {
    std::array<int, kNumCouplingEntries> entries{};
    int n = 0;
    for (int l = 0; l < kNumLegs; ++l)
      for (int m = 0; m < kNumLegs; ++m)
        if (l != m)
          for (const int i : leg_coordinates(l))
            for (const int j : leg_coordinates(m)) entries[n++] = j * kNumCoordinates + i;
    return entries;
  }

  // Entries between two different legs must be zero.
  static bool legs_uncoupled(const Matrix& a) {
    static constexpr std::array<int, kNumCouplingEntries> kEntries = coupling_entries();
    return entries_all_zero(a, kEntries);
  }

  bool eliminate(const Matrix& a) {
    TrunkMatrix schur = a.topLeftCorner<kTrunk, kTrunk>();
    for (int l = 0; l < kNumLegs; ++l) {
      const std::array<int, kLeg> c = leg_coordinates(l);
      LegMatrix leg;
      LegTrunk& leg_trunk = leg_trunk_solved_[l];
      for (int i = 0; i < kLeg; ++i) {
        for (int j = 0; j < kLeg; ++j) leg(i, j) = a(c[i], c[j]);
        leg_trunk.row(i) = a.row(c[i]).head<kTrunk>();
        trunk_leg_[l].col(i) = a.col(c[i]).head<kTrunk>();
      }
      if (!leg_lu_[l].compute(leg)) return false;
      leg_lu_[l].solve_in_place(leg_trunk);
      schur.noalias() -= trunk_leg_[l] * leg_trunk_solved_[l];
    }
    // A zero pivot or non-finite entries or factors: let the dense LU decide.
    if (!trunk_lu_.compute(schur)) return false;
    for (int l = 0; l < kNumLegs; ++l)
      if (!leg_trunk_solved_[l].allFinite()) return false;
    return true;
  }

  bool dense_ = true;
  std::array<FixedSizeLU<kLeg>, kNumLegs> leg_lu_;
  std::array<LegTrunk, kNumLegs> leg_trunk_solved_;  // A_ll^{-1} A_lt
  std::array<TrunkLeg, kNumLegs> trunk_leg_;         // A_tl
  FixedSizeLU<kTrunk> trunk_lu_;
  Eigen::PartialPivLU<Matrix> dense_lu_;
};

}  // namespace rover
