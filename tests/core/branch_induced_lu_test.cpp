// The block factorization on the coordinate tree (core/branch_induced_lu.hpp):
// the rover's coordinates form the documented trunk with four legs, its mass
// matrix and its stiff force Jacobians have the branch-induced pattern the
// factorization relies on (a property of the model, checked at random
// states), its solutions agree with dense factorizations, and it falls back to
// a dense LU where the pattern does not hold or a block is singular.
#include "core/branch_induced_lu.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "core/equations_of_motion.hpp"
#include "core/force_jacobian.hpp"
#include "core/rosenbrock_w.hpp"
#include "model_fixtures.hpp"

namespace rover {
namespace {

using Parents = std::array<int, kNumCoordinates>;

// A random matrix with non-zeros exactly on the pattern, made diagonally
// dominant (so elimination without pivoting is safe), not symmetric.
CoordinateMatrix random_patterned_matrix(const Parents& parent, std::mt19937& rng) {
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  CoordinateMatrix a = CoordinateMatrix::Zero();
  for (int i = 0; i < kNumCoordinates; ++i)
    for (int j = 0; j < kNumCoordinates; ++j)
      if (testing::coordinates_related(i, j, parent)) a(i, j) = entry(rng);
  a.diagonal().array() += 2.0 * kNumCoordinates;
  return a;
}

double relative_error(const Coordinates& x, const Coordinates& reference) {
  return (x - reference).norm() / reference.norm();
}

// The shape the factorization assumes: a chain of kTrunk coordinates, then
// four legs hanging from its last one, each a chain from the top down.
TEST(BranchInducedLU, CoordinateTreeIsTheTrunkWithFourLegs) {
  const RoverModel model = testing::airborne_model();
  const Parents& parent = model.tree.coordinate_parent;
  EXPECT_EQ(parent[0], -1);
  for (int c = 1; c < BranchInducedLU::kTrunk; ++c) EXPECT_EQ(parent[c], c - 1);
  EXPECT_EQ(BranchInducedLU::kTrunk - 1, coord::bogie);
  std::vector<bool> seen(kNumCoordinates, false);
  for (int c = 0; c < BranchInducedLU::kTrunk; ++c) seen[c] = true;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    int above = BranchInducedLU::kTrunk - 1;
    for (const int c : BranchInducedLU::leg_coordinates(leg)) {
      EXPECT_EQ(parent[c], above) << "leg " << leg << ", coordinate " << kCoordinateNames[c];
      EXPECT_FALSE(seen[c]);
      seen[c] = true;
      above = c;
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), true), kNumCoordinates);
}

TEST(BranchInducedLU, MassMatrixHasThePatternAndIsSolvedAsByCholesky) {
  const RoverModel model = testing::airborne_model();
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 20; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    const CoordinateMatrix M = mass_matrix(model.tree, forward_kinematics(model.tree, q, u));
    for (int i = 0; i < kNumCoordinates; ++i)
      for (int j = 0; j < kNumCoordinates; ++j)
        if (!testing::coordinates_related(i, j, model.tree.coordinate_parent)) {
          EXPECT_EQ(M(i, j), 0.0) << i << ", " << j;
        }
    BranchInducedLU lu;
    ASSERT_TRUE(lu.compute(M));
    Coordinates b;
    for (int i = 0; i < kNumCoordinates; ++i) b[i] = normal(rng);
    EXPECT_LT(relative_error(lu.solve(b), M.llt().solve(b)), 1e-12);
  }
}

TEST(BranchInducedLU, IterationMatrixAtContactHasThePattern) {
  const RoverModel model = make_rover_model(default_rover_parameters(), Terrain::flat(0.0));
  const ModelInputs inputs = nominal_inputs(model.parameters);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> small(-0.05, 0.05);
  int checked = 0;
  for (int trial = 0; trial < 10; ++trial) {
    Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
    for (int i = 3; i < kNumCoordinates; ++i) q[i] = small(rng);
    for (int i = 0; i < kNumCoordinates; ++i) u[i] = 10.0 * small(rng);
    q[coord::z] = 0.226;  // the wheels a few millimetres deep (wheel bottoms 0.2285 m below G)
    DynamicsWorkspace ws;
    compute_dynamics(model, ws, inputs, q, u);
    MechanicalLinearization<kNumCoordinates> lin;
    lin.mass = ws.mass_matrix;
    const StiffForceJacobian jac = stiff_force_jacobian(model, ws, inputs, q, u);
    lin.d_force_d_speed = jac.d_speed;
    lin.d_force_d_position = jac.d_position;
    if (jac.d_position.cwiseAbs().maxCoeff() < 1e3) continue;  // no contact pushing
    const CoordinateMatrix a = ros34pw2_iteration_matrix(lin, 1e-3);
    BranchInducedLU lu;
    EXPECT_TRUE(lu.compute(a)) << "trial " << trial;
    const Coordinates b = Coordinates::LinSpaced(-1.0, 2.0);
    EXPECT_LT(relative_error(lu.solve(b), a.partialPivLu().solve(b)), 1e-10);
    ++checked;
  }
  EXPECT_GE(checked, 5);
}

TEST(BranchInducedLU, UnsymmetricPatternedMatricesAgreeWithPartialPivoting) {
  const RoverModel model = testing::airborne_model();
  const Parents& parent = model.tree.coordinate_parent;
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const CoordinateMatrix a = random_patterned_matrix(parent, rng);
    BranchInducedLU lu;
    ASSERT_TRUE(lu.compute(a));
    const Eigen::Matrix<double, kNumCoordinates, 3> b = Eigen::Matrix<double, kNumCoordinates, 3>::Random();
    const Eigen::Matrix<double, kNumCoordinates, 3> x = lu.solve(b);
    EXPECT_LT((a * x - b).norm() / b.norm(), 1e-13);
  }
}

TEST(BranchInducedLU, PivotsWithinALegAndFallsBackOffThePatternOrOnASingularBlock) {
  const RoverModel model = testing::airborne_model();
  const Parents& parent = model.tree.coordinate_parent;
  std::mt19937 rng(9);
  const Coordinates b = Coordinates::LinSpaced(1.0, 3.0);
  BranchInducedLU lu;

  // A permutation block on a leg's last two coordinates: elimination without
  // pivoting would meet a zero pivot; the leg's LU pivots.
  CoordinateMatrix swapped = random_patterned_matrix(parent, rng);
  const int steer = coord::steer(2), spin = coord::spin(2);
  swapped(steer, steer) = swapped(spin, spin) = 0.0;
  swapped(steer, spin) = swapped(spin, steer) = 1.0;
  EXPECT_TRUE(lu.compute(swapped));
  EXPECT_LT((swapped * lu.solve(b) - b).norm() / b.norm(), 1e-12);

  // An entry coupling two legs: outside the pattern.
  CoordinateMatrix coupled = random_patterned_matrix(parent, rng);
  coupled(coord::spin(0), coord::spin(1)) = 0.5;
  EXPECT_FALSE(lu.compute(coupled));
  EXPECT_TRUE(lu.used_dense_fallback());
  EXPECT_LT((coupled * lu.solve(b) - b).norm() / b.norm(), 1e-13);

  // A leg block of zeros: singular, although the whole matrix is regular
  // (the leg couples to the trunk like a saddle point).
  CoordinateMatrix saddle = random_patterned_matrix(parent, rng);
  for (const int i : BranchInducedLU::leg_coordinates(1))
    for (const int j : BranchInducedLU::leg_coordinates(1)) saddle(i, j) = 0.0;
  ASSERT_GT(std::abs(saddle.determinant()), 0.0);
  EXPECT_FALSE(lu.compute(saddle));
  EXPECT_LT((saddle * lu.solve(b) - b).norm() / b.norm(), 1e-10);

  // And it recovers on the next patterned matrix.
  const CoordinateMatrix regular = random_patterned_matrix(parent, rng);
  EXPECT_TRUE(lu.compute(regular));
  EXPECT_FALSE(lu.used_dense_fallback());
  EXPECT_LT((regular * lu.solve(b) - b).norm() / b.norm(), 1e-13);
}

}  // namespace
}  // namespace rover
