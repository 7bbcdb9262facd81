// Cholesky at compile-time sizes (core/fixed_size_llt.hpp): a factor built
// from a known integer L is recovered exactly, L L^T rebuilds random
// symmetric positive definite matrices and L is Eigen's (the Cholesky factor
// is unique), solutions agree with Eigen's LLT and satisfy the system, only
// the lower triangle is read, and matrices that are not positive definite or
// not finite are reported.
#include "core/fixed_size_llt.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <gtest/gtest.h>

namespace rover {
namespace {

template <int N>
Eigen::Matrix<double, N, N> random_spd(std::mt19937& rng) {
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  const Eigen::Matrix<double, N, N> b = Eigen::Matrix<double, N, N>::NullaryExpr([&] { return entry(rng); });
  // B B^T is positive semidefinite; the shift bounds the condition number.
  return b * b.transpose() + 0.1 * Eigen::Matrix<double, N, N>::Identity();
}

template <int N>
void expect_factors_and_solves_like_eigen(std::mt19937& rng) {
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix<double, N, N> a = random_spd<N>(rng);
    FixedSizeLLT<N> llt;
    ASSERT_TRUE(llt.compute(a)) << "trial " << trial;
    const Eigen::Matrix<double, N, N> l = llt.matrix_l();
    const Eigen::LLT<Eigen::Matrix<double, N, N>> reference(a);
    const Eigen::Matrix<double, N, N> l_reference = reference.matrixL();
    EXPECT_LE((l * l.transpose() - a).norm(), 1e-15 * N * a.norm()) << "trial " << trial;
    EXPECT_LE((l - l_reference).norm(), 1e-13 * l_reference.norm()) << "trial " << trial;
    EXPECT_GT(l.diagonal().minCoeff(), 0.0);

    const Eigen::Matrix<double, N, 3> b = Eigen::Matrix<double, N, 3>::NullaryExpr([&] { return entry(rng); });
    const Eigen::Matrix<double, N, 3> x = llt.solve(b);
    const Eigen::Matrix<double, N, 3> x_reference = reference.solve(b);
    const double condition = a.norm() * a.inverse().norm();
    EXPECT_LE((x - x_reference).norm(), 1e-14 * condition * x_reference.norm()) << "trial " << trial;
    EXPECT_LE((a * x - b).norm(), 1e-14 * a.norm() * x.norm()) << "trial " << trial;

    // The two triangular halves: L y = b, then L^T x = y.
    Eigen::Matrix<double, N, 1> v = b.col(0);
    llt.solve_lower_in_place(v);
    EXPECT_LE((l * v - b.col(0)).norm(), 1e-14 * l.norm() * v.norm());
    const Eigen::Matrix<double, N, 1> y = v;
    llt.solve_lower_transposed_in_place(v);
    EXPECT_LE((l.transpose() * v - y).norm(), 1e-14 * l.norm() * v.norm());
    EXPECT_LE((v - x.col(0)).norm(), 1e-15 * x.col(0).norm());
  }
}

TEST(FixedSizeLLT, FactorsAndSolvesRandomSpdSystemsAsEigen) {
  std::mt19937 rng(17);
  expect_factors_and_solves_like_eigen<1>(rng);
  expect_factors_and_solves_like_eigen<4>(rng);
  expect_factors_and_solves_like_eigen<7>(rng);
}

TEST(FixedSizeLLT, RecoversAKnownFactor) {
  // A = L L^T in integers: every step of the factorization is exact but the
  // square roots, which are of perfect squares.
  Eigen::Matrix4d l_known;
  l_known << 2, 0, 0, 0,  //
      -1, 3, 0, 0,        //
      4, 1, 1, 0,         //
      0, 2, -3, 5;
  const Eigen::Matrix4d a = l_known * l_known.transpose();
  FixedSizeLLT<4> llt;
  ASSERT_TRUE(llt.compute(a));
  EXPECT_EQ(llt.matrix_l(), l_known);
  const Eigen::Vector4d x_true(1.0, -2.0, 0.5, 3.0);
  Eigen::Vector4d b = a * x_true;
  llt.solve_in_place(b);
  EXPECT_LE((b - x_true).norm(), 1e-13);
}

TEST(FixedSizeLLT, ReadsOnlyTheLowerTriangle) {
  std::mt19937 rng(4);
  const Eigen::Matrix<double, 7, 7> a = random_spd<7>(rng);
  Eigen::Matrix<double, 7, 7> lower_only = a;
  lower_only.triangularView<Eigen::StrictlyUpper>().setConstant(std::numeric_limits<double>::quiet_NaN());
  FixedSizeLLT<7> llt, llt_lower;
  ASSERT_TRUE(llt.compute(a));
  ASSERT_TRUE(llt_lower.compute(lower_only));
  EXPECT_EQ(llt_lower.matrix_l(), llt.matrix_l());
  const Eigen::Matrix<double, 7, 1> b = Eigen::Matrix<double, 7, 1>::LinSpaced(-1.0, 1.0);
  EXPECT_EQ(llt_lower.solve(b), llt.solve(b));
}

TEST(FixedSizeLLT, ReportsMatricesThatAreNotPositiveDefiniteOrNotFinite) {
  FixedSizeLLT<4> llt;
  // Symmetric but indefinite: eigenvalues 3 and -1 in the leading 2 x 2.
  Eigen::Matrix4d indefinite = Eigen::Matrix4d::Identity();
  indefinite(0, 0) = indefinite(1, 1) = 1.0;
  indefinite(1, 0) = indefinite(0, 1) = 2.0;
  EXPECT_FALSE(llt.compute(indefinite));
  // Positive semidefinite and singular: a zero last pivot.
  Eigen::Matrix4d semidefinite = Eigen::Matrix4d::Identity();
  semidefinite(3, 3) = 0.0;
  EXPECT_FALSE(llt.compute(semidefinite));
  EXPECT_FALSE(llt.compute(Eigen::Matrix4d::Zero()));
  EXPECT_FALSE(llt.compute(-Eigen::Matrix4d::Identity()));
  // A non-finite entry below the diagonal reaches a later pivot.
  Eigen::Matrix4d with_nan = Eigen::Matrix4d::Identity();
  with_nan(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(llt.compute(with_nan));
  Eigen::Matrix4d with_infinity = Eigen::Matrix4d::Identity();
  with_infinity(3, 0) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(llt.compute(with_infinity));
  Eigen::Matrix4d infinite_diagonal = Eigen::Matrix4d::Identity();
  infinite_diagonal(3, 3) = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(llt.compute(infinite_diagonal));
  EXPECT_TRUE(llt.compute(Eigen::Matrix4d::Identity()));
  EXPECT_EQ(llt.matrix_l(), Eigen::Matrix4d::Identity());
}

}  // namespace
}  // namespace rover
