// Block Cholesky factorization of the 23 x 23 mass matrix M(q) of the SA
// model (docs/model.md §4) on its coordinate tree, without fill-in
// (R. Featherstone, "Efficient factorization of the joint-space inertia
// matrix for branched kinematic trees", IJRR 24 (2005) 487-500).
//
// The layout is that of branch_induced_lu.hpp (a trunk of kTrunk coordinates
// carrying four legs of four, leg_coordinates()), and so is the order of
// elimination: legs first. M is symmetric positive definite, and so are its
// leg blocks M_ll and the trunk Schur complement, so with the legs ordered
// first
//     [ M_ll  M_lt ]   [ L_l   0  ] [ L_l^T  W_l  ]
//     [ M_tl  M_tt ] = [ W_l^T L_t ] [  0    L_t^T ],
//     M_ll = L_l L_l^T,   W_l = L_l^{-1} M_lt,
//     S = M_tt - sum_l W_l^T W_l = L_t L_t^T,
// one Cholesky factor per block (fixed_size_llt.hpp). Against the LU of the
// same blocks this needs no pivot search, half the arithmetic per block, only
// one of the two off-diagonal blocks (M_tl = M_lt^T), and one triangular solve
// less per leg in the elimination.
//
// Only the lower triangle of the matrix enters the result (the symmetric
// matrix it defines is the one factorized). A lower triangle with an entry
// coupling two legs, or blocks that are not positive definite or not finite,
// falls back to a dense LU with partial pivoting of that symmetric matrix, so
// solve() is always valid for a regular matrix.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/LU>

#include "core/branch_induced_lu.hpp"
#include "core/coordinates.hpp"
#include "core/fixed_size_llt.hpp"
#include "core/rover_parameters.hpp"

namespace rover {

class BranchInducedLLT {
 public:
  static constexpr int kTrunk = BranchInducedLU::kTrunk;
  static constexpr int kLeg = BranchInducedLU::kLeg;
  using Matrix = CoordinateMatrix;
  using Vector = Coordinates;

  // Returns true if the block Cholesky was used, false if the dense fallback
  // was.
  bool compute(const Matrix& a) {
    dense_ = !legs_uncoupled(a) || !eliminate(a);
    if (dense_) dense_lu_.compute(Matrix(a.selfadjointView<Eigen::Lower>()));
    return !dense_;
  }

  Vector solve(const Vector& b) const {
    if (dense_) return dense_lu_.solve(b);
    // Forward: L_l y_l = b_l, then L_t y_t = b_t - sum_l W_l^T y_l.
    TrunkVector x_trunk = b.head<kTrunk>();
    std::array<LegVector, kNumLegs> y;
    for (int l = 0; l < kNumLegs; ++l) {
      y[l] = BranchInducedLU::gather(b, l);
      leg_llt_[l].solve_lower_in_place(y[l]);
      x_trunk.noalias() -= reduced_leg_trunk_[l].transpose() * y[l];
    }
    // Back: L_t^T x_t = y_t, then L_l^T x_l = y_l - W_l x_t.
    trunk_llt_.solve_in_place(x_trunk);
    Vector x;
    x.head<kTrunk>() = x_trunk;
    for (int l = 0; l < kNumLegs; ++l) {
      LegVector x_leg = y[l];
      x_leg.noalias() -= reduced_leg_trunk_[l] * x_trunk;
      leg_llt_[l].solve_lower_transposed_in_place(x_leg);
      const std::array<int, kLeg> c = BranchInducedLU::leg_coordinates(l);
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
  // Row-major: the forward substitution updates whole rows of W_l, and
  // W_l^T W_l reads its rows as contiguous columns.
  using LegTrunk = Eigen::Matrix<double, kLeg, kTrunk, Eigen::RowMajor>;

  // The positions, in the column-major storage of a 23 x 23 matrix, of the
  // entries of its lower triangle that couple two different legs.
  static constexpr int kNumCouplingEntries = kLeg * kLeg * kNumLegs * (kNumLegs - 1) / 2;
  static constexpr std::array<int, kNumCouplingEntries> coupling_entries() {
    std::array<int, kNumCouplingEntries> entries{};
    int n = 0;
    for (int l = 1; l < kNumLegs; ++l)
      for (int m = 0; m < l; ++m)
        for (const int i : BranchInducedLU::leg_coordinates(l))
          for (const int j : BranchInducedLU::leg_coordinates(m))
            entries[n++] = std::min(i, j) * kNumCoordinates + std::max(i, j);
    return entries;
  }

  // Entries between two different legs, in the lower triangle, must be zero
  // (a NaN there counts as coupling).
  static bool legs_uncoupled(const Matrix& a) {
    static constexpr std::array<int, kNumCouplingEntries> kEntries = coupling_entries();
    return entries_all_zero(a, kEntries);
  }

  // The leg coordinates come after the trunk's and rise down each leg, so the
  // lower triangles of a leg block and of the trunk block, and the leg-trunk
  // rows, are in the lower triangle of a.
  bool eliminate(const Matrix& a) {
    TrunkMatrix schur = a.topLeftCorner<kTrunk, kTrunk>();
    for (int l = 0; l < kNumLegs; ++l) {
      const std::array<int, kLeg> c = BranchInducedLU::leg_coordinates(l);
      LegMatrix leg;
      LegTrunk& reduced = reduced_leg_trunk_[l];
      for (int i = 0; i < kLeg; ++i) {
        for (int j = 0; j <= i; ++j) leg(i, j) = a(c[i], c[j]);
        reduced.row(i) = a.row(c[i]).head<kTrunk>();
      }
      if (!leg_llt_[l].compute(leg)) return false;
      leg_llt_[l].solve_lower_in_place(reduced);
      schur.noalias() -= reduced.transpose() * reduced;
    }
    // A non-finite entry of some W_l reaches the diagonal of the Schur
    // complement through W_l^T W_l, so a successful trunk factorization also
    // means finite W_l.
    return trunk_llt_.compute(schur);
  }

  bool dense_ = true;
  std::array<FixedSizeLLT<kLeg>, kNumLegs> leg_llt_;
  std::array<LegTrunk, kNumLegs> reduced_leg_trunk_;  // W_l = L_l^{-1} A_lt
  FixedSizeLLT<kTrunk> trunk_llt_;
  Eigen::PartialPivLU<Matrix> dense_lu_;
};

}  // namespace rover
