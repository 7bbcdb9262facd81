// LU factorization with partial pivoting of a small matrix whose size is
// known at compile time (the 4 x 4 leg blocks and the 7 x 7 trunk Schur
// complement of branch_induced_lu.hpp).
//
// The algorithm is the textbook one (Golub and Van Loan, Matrix Computations,
// 4th ed., Alg. 3.4.1): at step k the largest entry of column k at or below
// the diagonal is swapped onto it, the column below is divided by it, and the
// trailing block gets the rank-one update. Eigen's PartialPivLU does the same
// arithmetic, but through kernels written for run-time sizes (strided
// references, blocked triangular solves with packing), which for a 4 x 4
// block cost several times the arithmetic; here every loop has a
// compile-time trip count and the compiler unrolls it.
//
// compute() reports a zero pivot or a non-finite factor by returning false;
// the caller decides what to do then (branch_induced_lu.hpp falls back to a
// dense LU).
#pragma once

#include <array>
#include <cmath>
#include <utility>

#include <Eigen/Core>

namespace rover {

template <int N>
class FixedSizeLU {
 public:
  using Matrix = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N, 1>;

  // Factorizes P a = L U (L unit lower triangular, stored below the diagonal
  // of lu_; U on and above it). Returns false if a pivot is zero or any
  // factor is not finite.
  bool compute(const Matrix& a) {
    lu_ = a;
    bool finite = true;
    for (int k = 0; k < N; ++k) {
      int pivot = k;
      double largest = std::abs(lu_(k, k));
      for (int i = k + 1; i < N; ++i)
        if (std::abs(lu_(i, k)) > largest) {
          largest = std::abs(lu_(i, k));
          pivot = i;
        }
      row_of_step_[k] = pivot;
      if (!(largest > 0.0)) return false;  // zero or NaN column
      if (pivot != k)
        for (int j = 0; j < N; ++j) std::swap(lu_(k, j), lu_(pivot, j));
      const double inverse_pivot = 1.0 / lu_(k, k);
      for (int i = k + 1; i < N; ++i) lu_(i, k) *= inverse_pivot;
      for (int j = k + 1; j < N; ++j) {
        const double u_kj = lu_(k, j);
        for (int i = k + 1; i < N; ++i) lu_(i, j) -= lu_(i, k) * u_kj;
      }
      finite = finite && std::isfinite(inverse_pivot);
    }
    return finite && lu_.allFinite();
  }

  // Solves a x = b for every column of b, in place.
  template <int Columns>
  void solve_in_place(Eigen::Matrix<double, N, Columns>& b) const {
    if constexpr (N > 1)  // (a 1 x 1 has no row to exchange)
      for (int k = 0; k < N; ++k)
        if (row_of_step_[k] != k) b.row(k).swap(b.row(row_of_step_[k]));
    for (int c = 0; c < b.cols(); ++c) {
      for (int i = 1; i < N; ++i) {
        double sum = b(i, c);
        for (int j = 0; j < i; ++j) sum -= lu_(i, j) * b(j, c);
        b(i, c) = sum;
      }
      for (int i = N - 1; i >= 0; --i) {
        double sum = b(i, c);
        for (int j = i + 1; j < N; ++j) sum -= lu_(i, j) * b(j, c);
        b(i, c) = sum / lu_(i, i);
      }
    }
  }

  template <int Columns>
  Eigen::Matrix<double, N, Columns> solve(const Eigen::Matrix<double, N, Columns>& b) const {
    Eigen::Matrix<double, N, Columns> x = b;
    solve_in_place(x);
    return x;
  }

  // L and U packed in one matrix (L's unit diagonal implied).
  const Matrix& packed_factors() const { return lu_; }

 private:
  Matrix lu_ = Matrix::Zero();
  std::array<int, N> row_of_step_{};  // row swapped with row k at step k
};

}  // namespace rover
