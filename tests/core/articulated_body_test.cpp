// The articulated-body solve (core/articulated_body.hpp) against the formed
// mass matrix of Kane's equations (core/dynamics.hpp): M (M^{-1} tau) = tau
// and M^{-1} (M x) = x at random states, including the extreme joint angles
// of the legs and a tumbled chassis, and a degenerate tree is reported.
#include "core/articulated_body.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/dynamics.hpp"
#include "model_fixtures.hpp"

namespace rover {
namespace {

double relative_error(const Coordinates& a, const Coordinates& b) { return (a - b).norm() / b.norm(); }

Coordinates random_vector(std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Coordinates v;
  for (int i = 0; i < kNumCoordinates; ++i) v[i] = normal(rng);
  return v;
}

TEST(ArticulatedBody, SolvesTheMassMatrixOfKanesEquations) {
  const RoverModel model = testing::airborne_model();
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    const TreeKinematics kin = forward_kinematics(model.tree, q, u);
    const CoordinateMatrix M = mass_matrix(model.tree, kin);
    const Coordinates tau = random_vector(rng);
    const std::optional<Coordinates> a = articulated_body_solve(model.tree, kin, tau);
    ASSERT_TRUE(a.has_value());
    // The residual, against the size of the terms it balances.
    EXPECT_LT((M * *a - tau).norm() / (M.norm() * a->norm()), 1e-14) << "trial " << trial;
    EXPECT_LT(relative_error(*a, M.llt().solve(tau)), 1e-11) << "trial " << trial;
    const Coordinates x = random_vector(rng);
    EXPECT_LT(relative_error(*articulated_body_solve(model.tree, kin, M * x), x), 1e-11) << "trial " << trial;
  }
}

TEST(ArticulatedBody, HoldsForATumbledChassisAndFoldedLegs) {
  const RoverModel model = testing::airborne_model();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> angle(-3.0, 3.0);
  for (int trial = 0; trial < 20; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    for (int c = coord::yaw; c < kNumCoordinates; ++c) q[c] = angle(rng);
    q[coord::pitch] = std::clamp(q[coord::pitch], -1.4, 1.4);  // away from the Euler angles' singularity
    const TreeKinematics kin = forward_kinematics(model.tree, q, u);
    const CoordinateMatrix M = mass_matrix(model.tree, kin);
    const Coordinates tau = random_vector(rng);
    const std::optional<Coordinates> a = articulated_body_solve(model.tree, kin, tau);
    ASSERT_TRUE(a.has_value());
    EXPECT_LT(relative_error(*a, M.llt().solve(tau)), 1e-9) << "trial " << trial;
  }
}

// A leaf without mass below its joint: the joint's pivot D is zero, and M
// itself is singular.
TEST(ArticulatedBody, MasslessWheelIsReported) {
  RoverParameters p = default_rover_parameters();
  p.wheel.mass_kg = 0.0;
  p.wheel.inertia_kgm2.setZero();
  p.wheel.com_m.setZero();
  const RoverModel model = testing::airborne_model(p);
  std::mt19937 rng(2);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  const TreeKinematics kin = forward_kinematics(model.tree, q, u);
  EXPECT_FALSE(articulated_body_solve(model.tree, kin, random_vector(rng)).has_value());
}

TEST(ArticulatedBody, NonFiniteForceIsReported) {
  const RoverModel model = testing::airborne_model();
  std::mt19937 rng(3);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  const TreeKinematics kin = forward_kinematics(model.tree, q, u);
  Coordinates tau = random_vector(rng);
  tau[coord::spin(2)] = std::nan("");
  EXPECT_FALSE(articulated_body_solve(model.tree, kin, tau).has_value());
}

}  // namespace
}  // namespace rover
