// The block Cholesky on the coordinate tree (core/branch_induced_llt.hpp):
// the model's mass matrix at random states and random symmetric positive
// definite matrices with the branch-induced pattern are solved as by a dense
// Cholesky, to round-off, reading only the lower triangle; a matrix off the
// pattern, an indefinite one and a non-finite one fall back to the dense
// factorization, which still solves the regular ones.
#include "core/branch_induced_llt.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include "core/dynamics.hpp"
#include "core/equations_of_motion.hpp"
#include "model_fixtures.hpp"

namespace rover {
namespace {

using Parents = std::array<int, kNumCoordinates>;
using Rhs = Eigen::Matrix<double, kNumCoordinates, 3>;

// A random symmetric matrix with non-zeros exactly on the pattern, made
// strictly diagonally dominant with a positive diagonal: positive definite
// (Gershgorin).
CoordinateMatrix random_patterned_spd(const Parents& parent, std::mt19937& rng) {
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  CoordinateMatrix a = CoordinateMatrix::Zero();
  for (int i = 0; i < kNumCoordinates; ++i)
    for (int j = 0; j < i; ++j)
      if (testing::coordinates_related(i, j, parent)) a(i, j) = a(j, i) = entry(rng);
  a.diagonal().array() += kNumCoordinates;
  return a;
}

Rhs random_rhs(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  return Rhs::NullaryExpr([&] { return normal(rng); });
}

TEST(BranchInducedLLT, SolvesPatternedSpdMatricesAsDenseCholesky) {
  const RoverModel model = testing::airborne_model();
  std::mt19937 rng(21);
  for (int trial = 0; trial < 20; ++trial) {
    const CoordinateMatrix a = random_patterned_spd(model.tree.coordinate_parent, rng);
    BranchInducedLLT llt;
    ASSERT_TRUE(llt.compute(a));
    EXPECT_FALSE(llt.used_dense_fallback());
    const Rhs b = random_rhs(rng);
    const Rhs x = llt.solve(b);
    EXPECT_LT((x - a.llt().solve(b)).norm() / x.norm(), 1e-14) << "trial " << trial;
    EXPECT_LT((a * x - b).norm() / b.norm(), 1e-14) << "trial " << trial;
  }
}

TEST(BranchInducedLLT, MassMatrixIsSolvedAsByDenseCholesky) {
  const RoverModel model = testing::airborne_model();
  std::mt19937 rng(13);
  for (int trial = 0; trial < 20; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    const CoordinateMatrix M = mass_matrix(model.tree, forward_kinematics(model.tree, q, u));
    BranchInducedLLT llt;
    ASSERT_TRUE(llt.compute(M)) << "trial " << trial;
    const Rhs b = random_rhs(rng);
    const Rhs x = llt.solve(b);
    const Rhs x_dense = M.llt().solve(b);
    EXPECT_LT((x - x_dense).norm() / x_dense.norm(), 1e-12) << "trial " << trial;
    EXPECT_LT((M * x - b).norm() / (M.norm() * x.norm()), 1e-15) << "trial " << trial;
  }
}

// Stage 5 of the equations of motion factorizes M with the block Cholesky.
TEST(BranchInducedLLT, AccelerationOfTheEquationsOfMotionSolvesMassTimesAccelerationIsForcing) {
  const RoverModel model = testing::airborne_model();
  const ModelInputs inputs = nominal_inputs(model.parameters);
  std::mt19937 rng(8);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  DynamicsWorkspace ws;
  compute_dynamics(model, ws, inputs, q, u);
  EXPECT_FALSE(ws.mass_factorization.used_dense_fallback());
  EXPECT_LT((ws.mass_matrix * ws.acceleration - ws.forcing).norm() / ws.forcing.norm(), 1e-14);
}

TEST(BranchInducedLLT, ReadsOnlyTheLowerTriangle) {
  const RoverModel model = testing::airborne_model();
  std::mt19937 rng(2);
  const CoordinateMatrix a = random_patterned_spd(model.tree.coordinate_parent, rng);
  CoordinateMatrix lower_only = a;
  // Garbage above the diagonal, coupling the legs there too.
  lower_only.triangularView<Eigen::StrictlyUpper>().setConstant(std::numeric_limits<double>::quiet_NaN());
  BranchInducedLLT llt, llt_lower;
  ASSERT_TRUE(llt.compute(a));
  ASSERT_TRUE(llt_lower.compute(lower_only));
  const Rhs b = random_rhs(rng);
  EXPECT_EQ(llt_lower.solve(b), llt.solve(b));
}

TEST(BranchInducedLLT, FallsBackOffThePatternOnAnIndefiniteOrNonFiniteMatrixAndRecovers) {
  const RoverModel model = testing::airborne_model();
  const Parents& parent = model.tree.coordinate_parent;
  std::mt19937 rng(9);
  const Rhs b = random_rhs(rng);
  BranchInducedLLT llt;

  // An entry coupling two legs: outside the pattern, still positive definite.
  CoordinateMatrix coupled = random_patterned_spd(parent, rng);
  coupled(coord::spin(1), coord::spin(0)) = coupled(coord::spin(0), coord::spin(1)) = 0.5;
  EXPECT_FALSE(llt.compute(coupled));
  EXPECT_TRUE(llt.used_dense_fallback());
  EXPECT_LT((coupled * llt.solve(b) - b).norm() / b.norm(), 1e-14);

  // A leg block of zeros: a symmetric saddle point, regular but indefinite.
  CoordinateMatrix saddle = random_patterned_spd(parent, rng);
  for (const int i : BranchInducedLU::leg_coordinates(3))
    for (const int j : BranchInducedLU::leg_coordinates(3)) saddle(i, j) = 0.0;
  ASSERT_GT(std::abs(saddle.determinant()), 0.0);
  EXPECT_FALSE(llt.compute(saddle));
  EXPECT_LT((saddle * llt.solve(b) - b).norm() / b.norm(), 1e-12);

  // Positive definite leg blocks but a negative trunk diagonal: the Schur
  // complement is indefinite, found only at the trunk's factorization.
  CoordinateMatrix trunk_indefinite = random_patterned_spd(parent, rng);
  trunk_indefinite(coord::bogie, coord::bogie) = -trunk_indefinite(coord::bogie, coord::bogie);
  EXPECT_FALSE(llt.compute(trunk_indefinite));
  EXPECT_LT((trunk_indefinite * llt.solve(b) - b).norm() / b.norm(), 1e-13);

  // A NaN in a leg-trunk entry of the lower triangle.
  CoordinateMatrix with_nan = random_patterned_spd(parent, rng);
  with_nan(coord::steer(2), 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(llt.compute(with_nan));
  EXPECT_TRUE(llt.used_dense_fallback());
  EXPECT_FALSE(llt.solve(b).allFinite());

  // And it recovers on the next positive definite patterned matrix.
  const CoordinateMatrix regular = random_patterned_spd(parent, rng);
  EXPECT_TRUE(llt.compute(regular));
  EXPECT_FALSE(llt.used_dense_fallback());
  EXPECT_LT((regular * llt.solve(b) - b).norm() / b.norm(), 1e-14);
}

}  // namespace
}  // namespace rover
