// LU with partial pivoting at compile-time sizes (core/fixed_size_lu.hpp):
// solutions of random systems agree with Eigen's PartialPivLU and satisfy the
// system, the pivoting handles a zero on the diagonal, the factors rebuild the
// permuted matrix, and a singular or non-finite matrix is reported.
#include "core/fixed_size_lu.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/LU>
#include <gtest/gtest.h>

namespace rover {
namespace {

template <int N>
void expect_solves_like_partial_pivoting(std::mt19937& rng) {
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix<double, N, N> a = Eigen::Matrix<double, N, N>::NullaryExpr([&] { return entry(rng); });
    const Eigen::Matrix<double, N, 3> b = Eigen::Matrix<double, N, 3>::NullaryExpr([&] { return entry(rng); });
    FixedSizeLU<N> lu;
    ASSERT_TRUE(lu.compute(a));
    const Eigen::Matrix<double, N, 3> x = lu.solve(b);
    const Eigen::Matrix<double, N, 3> reference = Eigen::PartialPivLU<Eigen::Matrix<double, N, N>>(a).solve(b);
    const double condition = a.norm() * a.inverse().norm();
    EXPECT_LE((x - reference).norm(), 1e-14 * condition * reference.norm()) << "trial " << trial;
    EXPECT_LE((a * x - b).norm(), 1e-14 * a.norm() * x.norm()) << "trial " << trial;
  }
}

TEST(FixedSizeLU, SolvesRandomSystemsAsPartialPivoting) {
  std::mt19937 rng(7);
  expect_solves_like_partial_pivoting<1>(rng);
  expect_solves_like_partial_pivoting<4>(rng);
  expect_solves_like_partial_pivoting<7>(rng);
}

TEST(FixedSizeLU, PivotsPastAZeroDiagonalAndItsFactorsRebuildTheMatrix) {
  Eigen::Matrix4d a;
  a << 0, 2, 1, 0,  //
      3, 1, 0, 1,   //
      1, 0, 0, 2,   //
      0, 1, 4, 1;
  FixedSizeLU<4> lu;
  ASSERT_TRUE(lu.compute(a));
  const Eigen::Matrix4d& f = lu.packed_factors();
  const Eigen::Matrix4d l = f.triangularView<Eigen::UnitLower>();
  const Eigen::Matrix4d u = f.triangularView<Eigen::Upper>();
  // Every multiplier is at most 1 in magnitude (the pivot is the column's largest).
  EXPECT_LE(f.triangularView<Eigen::StrictlyLower>().toDenseMatrix().cwiseAbs().maxCoeff(), 1.0);
  // L U is a row permutation of a: every row of L U is a row of a, once.
  const Eigen::Matrix4d lu_product = l * u;
  std::array<bool, 4> used{};
  for (int i = 0; i < 4; ++i) {
    int match = -1;
    for (int r = 0; r < 4; ++r)
      if (!used[r] && (lu_product.row(i) - a.row(r)).norm() < 1e-14) match = r;
    ASSERT_GE(match, 0) << "row " << i << " of L U is no row of a";
    used[match] = true;
  }
  const Eigen::Vector4d x_true(1.0, -2.0, 0.5, 3.0);
  Eigen::Vector4d b = a * x_true;
  lu.solve_in_place(b);
  EXPECT_LE((b - x_true).norm(), 1e-14);
}

TEST(FixedSizeLU, ReportsSingularAndNonFiniteMatrices) {
  Eigen::Matrix4d singular;  // a zero row stays zero through the updates: a zero pivot
  singular << 1, 2, 3, 4, 0, 0, 0, 0, 5, 1, 2, 0, 1, 1, 1, 1;
  FixedSizeLU<4> lu;
  EXPECT_FALSE(lu.compute(singular));
  EXPECT_FALSE(lu.compute(Eigen::Matrix4d::Zero()));
  Eigen::Matrix4d with_nan = Eigen::Matrix4d::Identity();
  with_nan(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(lu.compute(with_nan));
  Eigen::Matrix4d with_infinity = Eigen::Matrix4d::Identity();
  with_infinity(0, 3) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(lu.compute(with_infinity));
  EXPECT_TRUE(lu.compute(Eigen::Matrix4d::Identity()));
}

}  // namespace
}  // namespace rover
