// LU factorization without fill-in of a matrix with branch-induced sparsity
// (R. Featherstone, "Efficient factorization of the joint-space inertia
// matrix for branched kinematic trees", IJRR 24 (2005) 487-500), used for the
// mass matrix M(q) of the right-hand side (docs/model.md §4) and for the
// iteration matrix M0 - h g D - h^2 g^2 K of the stiff integrator (§9).
//
// The coordinates of a kinematic tree form a tree of their own: coordinate
// parent[c] < c drives the nearest joint above those of c. Entry (i, j) of M
// is non-zero only if i is an ancestor of j or j one of i (a joint moves only
// the bodies below it), and so is every entry of the stiff force Jacobians D
// and K (a contact force acts on the joints above its wheel, and depends on
// them only). Eliminating the coordinates leaves first then creates no
// fill-in: pivot k updates only entries (i, j) with i, j ancestors of k, which
// are related. The work is the sum over coordinates of their depth squared:
// about 1.3e3 multiply-adds for the 23 coordinates of the rover, against
// 23^3 / 3 = 4.1e3 for a dense LU, and with none of a general routine's
// blocking overhead at this size.
//
// Unlike Featherstone's LTDL this is the unsymmetric variant (the iteration
// matrix is not symmetric), without pivoting. It is stable where Gaussian
// elimination without pivoting is, as for the symmetric positive definite M
// and the iteration matrices of a dissipative system; compute() falls back to
// a dense LU with partial pivoting when a matrix has an entry outside the
// pattern or meets a pivot that is tiny, zero or not finite, so solve() is
// always as good as Eigen's PartialPivLU.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include <Eigen/Core>
#include <Eigen/LU>

namespace rover {

template <int N>
class BranchInducedLU {
  static_assert(N <= 64, "the pattern is kept as 64-bit masks");

 public:
  using Matrix = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N, 1>;
  using Parents = std::array<int, N>;

  BranchInducedLU() = default;

  // `parent[c]` is the parent coordinate of c (< c), or -1 at a root.
  // Returns true if the sparse elimination was used, false if the dense
  // fallback was (see the top of the file); solve() is valid either way.
  bool compute(const Matrix& a, const Parents& parent) {
    if (!tree_known_ || parent != parent_) learn_tree(parent);
    dense_ = !has_branch_induced_pattern(a) || !eliminate(a);
    if (dense_) dense_lu_.compute(a);
    return !dense_;
  }

  // The same for a symmetric matrix (M): Featherstone's L^T D L, half the
  // work, reading the lower triangle only. Not-positive pivots fall back.
  bool compute_symmetric(const Matrix& a, const Parents& parent) {
    if (!tree_known_ || parent != parent_) learn_tree(parent);
    dense_ = !has_branch_induced_lower_pattern(a) || !eliminate_symmetric(a);
    if (dense_) dense_lu_.compute(a.template selfadjointView<Eigen::Lower>());
    return !dense_;
  }

  Vector solve(const Vector& b) const {
    if (dense_) return dense_lu_.solve(b);
    return symmetric_ ? solve_symmetric(b) : solve_unsymmetric(b);
  }

  // Column by column, for a matrix right-hand side.
  template <typename Derived>
  Eigen::Matrix<double, N, Derived::ColsAtCompileTime> solve(const Eigen::MatrixBase<Derived>& b) const {
    Eigen::Matrix<double, N, Derived::ColsAtCompileTime> x(N, b.cols());
    for (Eigen::Index c = 0; c < b.cols(); ++c) x.col(c) = solve(Vector(b.col(c)));
    return x;
  }

  bool used_dense_fallback() const { return dense_; }

 private:
  Vector solve_unsymmetric(const Vector& b) const {
    Vector x = b;
    for (int k = N - 1; k >= 0; --k) {
      const double xk = x[k];
      for (int a = 0; a < depth_[k]; ++a) x[ancestors_[k][a]] -= factors_(ancestors_[k][a], k) * xk;
    }
    for (int k = 0; k < N; ++k) {
      double sum = x[k];
      for (int a = 0; a < depth_[k]; ++a) sum -= factors_(k, ancestors_[k][a]) * x[ancestors_[k][a]];
      x[k] = sum / factors_(k, k);
    }
    return x;
  }

  // x = L^{-1} D^{-1} L^{-T} b with L_kj = factors_(k, j), j above k.
  Vector solve_symmetric(const Vector& b) const {
    Vector x = b;
    for (int k = N - 1; k >= 0; --k) {
      const double xk = x[k];
      for (int a = 0; a < depth_[k]; ++a) x[ancestors_[k][a]] -= factors_(k, ancestors_[k][a]) * xk;
    }
    for (int k = 0; k < N; ++k) x[k] /= factors_(k, k);
    for (int k = 0; k < N; ++k) {
      double sum = x[k];
      for (int a = 0; a < depth_[k]; ++a) sum -= factors_(k, ancestors_[k][a]) * x[ancestors_[k][a]];
      x[k] = sum;
    }
    return x;
  }

  // The ancestors of every coordinate, nearest first, and per column the
  // mask of the rows related to it (itself, its ancestors, its descendants).
  void learn_tree(const Parents& parent) {
    parent_ = parent;
    related_.fill(0);
    for (int k = 0; k < N; ++k) {
      depth_[k] = 0;
      related_[k] |= std::uint64_t{1} << k;
      for (int i = parent[k]; i >= 0; i = parent[i]) {
        ancestors_[k][depth_[k]++] = i;
        related_[k] |= std::uint64_t{1} << i;
        related_[i] |= std::uint64_t{1} << k;
      }
    }
    tree_known_ = true;
  }

  bool has_branch_induced_pattern(const Matrix& a) const {
    for (int j = 0; j < N; ++j) {
      std::uint64_t nonzero = 0;
      for (int i = 0; i < N; ++i) nonzero |= std::uint64_t{a(i, j) != 0.0} << i;
      if (nonzero & ~related_[j]) return false;
    }
    return true;
  }

  bool has_branch_induced_lower_pattern(const Matrix& a) const {
    for (int j = 0; j < N; ++j) {
      std::uint64_t nonzero = 0;
      for (int i = j + 1; i < N; ++i) nonzero |= std::uint64_t{a(i, j) != 0.0} << i;
      if (nonzero & ~related_[j]) return false;
    }
    return true;
  }

  // Featherstone's LTDL: leaves first, pivot k scales its row of ancestors
  // into L and updates the lower triangle among them.
  bool eliminate_symmetric(const Matrix& a) {
    symmetric_ = true;
    factors_ = a;
    for (int k = N - 1; k >= 0; --k) {
      const double pivot = factors_(k, k);
      if (!std::isfinite(pivot) || !(pivot > 0.0)) return false;
      const int depth = depth_[k];
      const std::array<int, N>& above = ancestors_[k];
      for (int r = 0; r < depth; ++r) {
        const int i = above[r];
        const double ratio = factors_(k, i) / pivot;
        for (int c = r; c < depth; ++c) factors_(i, above[c]) -= ratio * factors_(k, above[c]);
        factors_(k, i) = ratio;
      }
    }
    return true;
  }

  // Leaves first: pivot k updates rows and columns of its ancestors. The
  // multipliers go where the eliminated entries (i, k), i above k, were;
  // row k keeps its entries (k, j), j above k, for the back substitution.
  bool eliminate(const Matrix& a) {
    constexpr double kTinyPivot = 1e3 * std::numeric_limits<double>::epsilon();
    symmetric_ = false;
    factors_ = a;
    for (int k = N - 1; k >= 0; --k) {
      const double pivot = factors_(k, k);
      if (!std::isfinite(pivot) || !(std::abs(pivot) > kTinyPivot * std::abs(a(k, k)))) return false;
      const int depth = depth_[k];
      const std::array<int, N>& above = ancestors_[k];
      for (int r = 0; r < depth; ++r) {
        const int i = above[r];
        const double multiplier = factors_(i, k) / pivot;
        factors_(i, k) = multiplier;
        if (multiplier == 0.0) continue;
        for (int c = 0; c < depth; ++c) factors_(i, above[c]) -= multiplier * factors_(k, above[c]);
      }
    }
    return true;
  }

  bool tree_known_ = false;
  Parents parent_{};
  std::array<std::array<int, N>, N> ancestors_{};
  std::array<int, N> depth_{};
  std::array<std::uint64_t, N> related_{};
  Matrix factors_ = Matrix::Zero();
  bool dense_ = true, symmetric_ = false;
  Eigen::PartialPivLU<Matrix> dense_lu_;
};

}  // namespace rover
