// Cholesky factorization a = L L^T of a small symmetric positive definite
// matrix whose size is known at compile time (the 4 x 4 leg blocks and the
// 7 x 7 trunk Schur complement of the mass matrix in branch_induced_llt.hpp).
//
// The algorithm is the textbook row-oriented Cholesky (Golub and Van Loan,
// Matrix Computations, 4th ed., Alg. 4.2.1, here by rows): row k of L is
// found from the rows above it by one inner product per entry, then its
// diagonal entry by a square root. Only the lower triangle of a is read. No
// pivot search is needed, and the arithmetic is half that of an LU
// (fixed_size_lu.hpp). Eigen's LLT does the same arithmetic through kernels
// for run-time sizes (dynamic-size blocks, the matrix 1-norm kept for a
// condition estimate): under callgrind (g++ -O3) its factorization of a
// 4 x 4 block takes about 390 instructions against 120 here, of a 7 x 7 about
// 1200 against 510, and a 4 x 7 triangular solve through it several times
// the arithmetic. Here every loop has a compile-time trip count and the
// compiler unrolls it.
//
// The reciprocals of the diagonal of L are kept, so that the triangular
// solves multiply instead of divide.
//
// compute() reports a pivot that is not positive and finite (a matrix that is
// not positive definite to working precision, or has non-finite entries) by
// returning false; the caller decides what to do then (branch_induced_llt.hpp
// falls back to a dense factorization).
#pragma once

#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace rover {

template <int N>
class FixedSizeLLT {
 public:
  using Matrix = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N, 1>;

  // Factorizes a = L L^T from the lower triangle of a. Returns false if a
  // pivot (the square of a diagonal entry of L) is not positive and finite.
  // A non-finite entry of a reaches a pivot through the square of the entry of
  // L it makes, so every factor is finite when this returns true.
  bool compute(const Matrix& a) {
    for (int k = 0; k < N; ++k) {
      for (int j = 0; j < k; ++j) {
        double sum = a(k, j);
        for (int m = 0; m < j; ++m) sum -= l_(k, m) * l_(j, m);
        l_(k, j) = sum * inverse_diagonal_[j];
      }
      double pivot = a(k, k);
      for (int m = 0; m < k; ++m) pivot -= l_(k, m) * l_(k, m);
      // Positive and finite; false for NaN too.
      if (!(pivot > 0.0 && pivot <= std::numeric_limits<double>::max())) return false;
      l_(k, k) = std::sqrt(pivot);
      inverse_diagonal_[k] = 1.0 / l_(k, k);
    }
    return true;
  }

  // Solves L y = b for every column of b, in place (forward substitution),
  // row by row: a row-major b is updated a whole row at a time.
  template <int Columns, int Options>
  void solve_lower_in_place(Eigen::Matrix<double, N, Columns, Options>& b) const {
    for (int i = 0; i < N; ++i) {
      for (int j = 0; j < i; ++j) b.row(i) -= l_(i, j) * b.row(j);
      b.row(i) *= inverse_diagonal_[i];
    }
  }

  // Solves L^T x = y for every column of y, in place (back substitution).
  template <int Columns, int Options>
  void solve_lower_transposed_in_place(Eigen::Matrix<double, N, Columns, Options>& y) const {
    for (int i = N - 1; i >= 0; --i) {
      for (int j = i + 1; j < N; ++j) y.row(i) -= l_(j, i) * y.row(j);
      y.row(i) *= inverse_diagonal_[i];
    }
  }

  // Solves a x = b for every column of b, in place.
  template <int Columns, int Options>
  void solve_in_place(Eigen::Matrix<double, N, Columns, Options>& b) const {
    solve_lower_in_place(b);
    solve_lower_transposed_in_place(b);
  }

  template <int Columns>
  Eigen::Matrix<double, N, Columns> solve(const Eigen::Matrix<double, N, Columns>& b) const {
    Eigen::Matrix<double, N, Columns> x = b;
    solve_in_place(x);
    return x;
  }

  // L, lower triangular with a positive diagonal (valid after compute()
  // returned true).
  Matrix matrix_l() const { return l_.template triangularView<Eigen::Lower>(); }

 private:
  Matrix l_ = Matrix::Zero();  // L on and below the diagonal; above it unused
  Vector inverse_diagonal_ = Vector::Zero();
};

}  // namespace rover
