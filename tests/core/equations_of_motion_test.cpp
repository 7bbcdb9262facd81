// The assembled equations of motion (core/equations_of_motion.cpp): energy
// conservation in free flight, left/right mirror symmetry, the right-hand side
// against the equations assembled stage by stage, F against its terms.
#include "core/equations_of_motion.hpp"

#include <algorithm>

#include <gtest/gtest.h>

// GCC 12 warns inside odeint's steppers (-Wmaybe-uninitialized), not about this code.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/external/eigen/eigen.hpp>
#pragma GCC diagnostic pop

#include "model_fixtures.hpp"

namespace rover {
namespace {

// Conservative rover: no S-structure damping, no servo damping, no drive.
RoverParameters conservative_parameters() {
  RoverParameters p = default_rover_parameters();
  p.s_structure.damping_c_q = 0.0;
  p.steering.damping_Nms_per_rad = 0.0;
  p.drive.gain_Nms_per_rad = 0.0;
  return p;
}

TEST(EquationsOfMotion, FreeFlightConservesEnergy) {
  const RoverModel model = testing::airborne_model(conservative_parameters());
  const ModelInputs inputs = nominal_inputs(model.parameters);
  StateVector x = StateVector::Zero();
  Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
  q[coord::z] = 1.0;
  q[coord::pitch] = 0.1;
  q[coord::roll] = -0.05;
  u[coord::x] = 0.3;
  u[coord::yaw] = 0.5;
  u[coord::bogie] = 2.0;
  // Excite the S-joints across the steep atan region and the steering springs.
  for (int leg = 0; leg < kNumLegs; ++leg) {
    q[coord::s_joint(leg, 0)] = 0.02 * (leg + 1);
    u[coord::s_joint(leg, 1)] = -1.5 + leg;
    q[coord::steer(leg)] = 0.2 * (leg - 1.5);
    u[coord::spin(leg)] = 5.0 * (leg + 1);
  }
  x << q, u;
  DynamicsWorkspace workspace;
  const double e0 = mechanical_energy(model, workspace, inputs, q, u);
  const double scale = std::abs(e0);
  using namespace boost::numeric::odeint;
  auto rhs = [&](const StateVector& s, StateVector& ds, double) { ds = state_derivative(model, workspace, inputs, s); };
  double max_drift = 0.0;
  auto observe = [&](const StateVector& s, double) {
    const double e = mechanical_energy(model, workspace, inputs, s.head<kNumCoordinates>(), s.tail<kNumCoordinates>());
    max_drift = std::max(max_drift, std::abs(e - e0) / scale);
  };
  integrate_adaptive(make_controlled(1e-11, 1e-11, runge_kutta_dopri5<StateVector, double, StateVector, double,
                                                                      vector_space_algebra>()),
                     rhs, x, 0.0, 0.2, 1e-5, observe);
  EXPECT_LT(max_drift, 1e-6) << "E0 = " << e0;
  // The motion really exercised the joints.
  EXPECT_GT(std::abs(x[coord::bogie] - q[coord::bogie]), 0.05);
}

// Mirror about the chassis x-z plane: y -> -y. Left and right legs swap.
Coordinates mirror(const Coordinates& v) {
  Coordinates m = v;
  m[coord::y] = -v[coord::y];
  m[coord::yaw] = -v[coord::yaw];
  m[coord::roll] = -v[coord::roll];
  m[coord::bogie] = -v[coord::bogie];
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const int other = leg ^ 1;  // FL <-> FR, RL <-> RR
    m[coord::s_joint(leg, 0)] = v[coord::s_joint(other, 0)];
    m[coord::s_joint(leg, 1)] = v[coord::s_joint(other, 1)];
    m[coord::steer(leg)] = -v[coord::steer(other)];
    m[coord::spin(leg)] = v[coord::spin(other)];
  }
  return m;
}

TEST(EquationsOfMotion, MirroredStateGivesMirroredAccelerations) {
  // On the ground (contact on), with preloads and set-points mirrored too.
  const RoverModel model = make_rover_model(default_rover_parameters());
  ModelInputs in = nominal_inputs(model.parameters);
  in.wheel_speed_ref_radps = {1.0, 2.0, 3.0, 4.0};
  in.steer_ref_rad = {0.1, 0.2, -0.1, 0.05};
  ModelInputs in_m = in;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const int other = leg ^ 1;
    in_m.preload_Nm[2 * leg] = in.preload_Nm[2 * other];
    in_m.preload_Nm[2 * leg + 1] = in.preload_Nm[2 * other + 1];
    in_m.wheel_speed_ref_radps[leg] = in.wheel_speed_ref_radps[other];
    in_m.steer_ref_rad[leg] = -in.steer_ref_rad[other];
  }
  std::mt19937 rng(4);
  DynamicsWorkspace workspace;
  for (int trial = 0; trial < 5; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    q[coord::z] = 0.20;  // low enough for some wheels to touch
    StateVector x, xm;
    x << q, u;
    xm << mirror(q), mirror(u);
    const StateVector dx = state_derivative(model, workspace, in, x);
    const StateVector dxm = state_derivative(model, workspace, in_m, xm);
    const Coordinates expected = mirror(dx.tail<kNumCoordinates>());
    EXPECT_LT((dxm.tail<kNumCoordinates>() - expected).cwiseAbs().maxCoeff(),
              1e-9 * std::max(1.0, expected.cwiseAbs().maxCoeff()));
  }
}

TEST(EquationsOfMotion, RightHandSideSolvesTheStagedEquations) {
  const RoverModel model = make_rover_model(default_rover_parameters());
  const ModelInputs in = nominal_inputs(model.parameters);
  std::mt19937 rng(8);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  q[coord::z] = 0.21;
  // The stages one by one into one workspace, the right-hand side into another.
  DynamicsWorkspace eom, workspace;
  compute_kinematics(model, eom, q, u);
  compute_contacts(model, eom);
  compute_mass_matrix(model, eom);
  compute_forcing(model, eom, in, q, u);
  StateVector x;
  x << q, u;
  const StateVector dx = state_derivative(model, workspace, in, x);
  const Coordinates residual = eom.mass_matrix * dx.tail<kNumCoordinates>() - eom.forcing;
  EXPECT_LT(residual.cwiseAbs().maxCoeff(), 1e-9 * eom.forcing.cwiseAbs().maxCoeff());
  EXPECT_EQ(dx.head<kNumCoordinates>(), u);
  int touching = 0;
  for (const auto& c : eom.contacts) touching += c.count;
  EXPECT_GT(touching, 0);
  EXPECT_NE(eom.forcing, eom.forcing_without_contact);
}

// The right-hand side without M (the articulated-body recursion) equals the
// one through M and its factors, with wheels on the ground, and leaves the
// workspace's M as it found it.
TEST(EquationsOfMotion, ArticulatedRightHandSideEqualsTheOneThroughTheMassMatrix) {
  const RoverModel model = make_rover_model(default_rover_parameters());
  const ModelInputs in = nominal_inputs(model.parameters);
  std::mt19937 rng(21);
  for (int trial = 0; trial < 20; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    q[coord::z] = 0.21;
    StateVector x;
    x << q, u;
    DynamicsWorkspace with_mass, without_mass;
    const StateVector expected = state_derivative(model, with_mass, in, x);
    without_mass.mass_matrix.setConstant(7.0);
    const StateVector dx = state_derivative_articulated(model, without_mass, in, x);
    EXPECT_EQ(dx.head<kNumCoordinates>(), u);
    EXPECT_LT((dx - expected).tail<kNumCoordinates>().norm(), 1e-10 * expected.tail<kNumCoordinates>().norm())
        << "trial " << trial;
    EXPECT_TRUE((without_mass.mass_matrix.array() == 7.0).all());
    EXPECT_EQ(without_mass.forcing, with_mass.forcing);
  }
}

// Stage 4's F against its terms built one by one: the contacts' J_P^T
// (F_n n + F_t) from their point Jacobians (paper eq. 9), gravity and
// inertia forces and the joint torques.
TEST(EquationsOfMotion, ForcingIsTheSumOfItsTermsWithContactsThroughTheirPointJacobians) {
  const RoverModel model = make_rover_model(default_rover_parameters());
  const ModelInputs in = nominal_inputs(model.parameters);
  std::mt19937 rng(33);
  for (int trial = 0; trial < 20; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    q[coord::z] = 0.21;
    DynamicsWorkspace eom;
    compute_kinematics(model, eom, q, u);
    compute_contacts(model, eom);
    compute_forcing(model, eom, in, q, u);
    Coordinates contact = Coordinates::Zero();
    int points = 0;
    for (int leg = 0; leg < kNumLegs; ++leg)
      for (int k = 0; k < eom.contacts[leg].count; ++k, ++points) {
        const ContactPoint& c = eom.contacts[leg].points[k];
        contact += point_jacobian(model.tree, eom.kinematics, node::wheel(leg), c.point_m).transpose() *
                   (c.normal_force_N * c.normal + c.friction_force_N);
      }
    ASSERT_GT(points, 0);
    const Coordinates without_contact =
        gravity_and_inertia_forces(model.tree, eom.kinematics, model.parameters.gravity_mps2) +
        joint_forces(model.parameters, in, q, u);
    const double scale = std::max(without_contact.cwiseAbs().maxCoeff(), contact.cwiseAbs().maxCoeff());
    EXPECT_LT((eom.forcing_without_contact - without_contact).cwiseAbs().maxCoeff(), 1e-13 * scale)
        << "trial " << trial;
    EXPECT_LT((eom.forcing - eom.forcing_without_contact - contact).cwiseAbs().maxCoeff(), 1e-12 * scale)
        << "trial " << trial;
  }
}

TEST(EquationsOfMotion, StandingStillOnFlatGroundFeelsOnlyTheWeightThroughTheWheels) {
  // Static check: at rest on the ground, the vertical contact force balances
  // the weight when the accelerations vanish: sum of F_n = m g at equilibrium
  // is not imposed here, but the vertical generalized force equals the sum of
  // the vertical contact forces minus the weight.
  const RoverModel model = make_rover_model(default_rover_parameters());
  const ModelInputs in = nominal_inputs(model.parameters);
  Coordinates q = Coordinates::Zero();
  q[coord::z] = 0.2285 - 0.002;  // 2 mm penetration for every wheel
  DynamicsWorkspace eom;
  compute_dynamics(model, eom, in, q, Coordinates::Zero());
  double total_normal = 0.0;
  for (const auto& c : eom.contacts) {
    ASSERT_EQ(c.count, 1);
    EXPECT_NEAR(c.points[0].penetration_m, 0.002, 1e-12);
    total_normal += c.total_normal_force_N();
  }
  EXPECT_NEAR(eom.forcing[coord::z], total_normal - model.tree.total_mass_kg * model.parameters.gravity_mps2,
              1e-9);
  EXPECT_NEAR(total_normal, 4 * 1e6 * std::pow(0.002, 1.8), 1e-9);
}

}  // namespace
}  // namespace rover
