// Kane's equations (core/dynamics.cpp) checked against independent routes:
// M from body Jacobians, the velocity terms from Lagrange's equations by finite
// differences of M, gravity from the potential, and the joint torques from
// their potentials.
#include "core/dynamics.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include "core/s_structure.hpp"
#include "model_fixtures.hpp"

namespace rover {
namespace {

const RoverParameters kParams = default_rover_parameters();
const KinematicTree kTree = build_kinematic_tree(kParams);

CoordinateMatrix mass_at(const Coordinates& q) {
  return mass_matrix(kTree, forward_kinematics(kTree, q, Coordinates::Zero()));
}

TEST(Dynamics, MassMatrixIsSymmetricPositiveDefinite) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 20; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    const CoordinateMatrix M = mass_at(q);
    EXPECT_LT((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-15);
    const double smallest = Eigen::SelfAdjointEigenSolver<CoordinateMatrix>(M).eigenvalues()(0);
    EXPECT_GT(smallest, 0.0);
  }
}

TEST(Dynamics, MassMatrixEqualsSumOverBodiesOfJacobianProducts) {
  // Paper eq. 4 written as M = sum_b m_b Jv^T Jv + Jw^T I_b Jw, with Jv from
  // point_jacobian and Jw from finite differences of the body rotations.
  std::mt19937 rng(2);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  const TreeKinematics kin = forward_kinematics(kTree, q, u);
  CoordinateMatrix M = CoordinateMatrix::Zero();
  for (int b = 0; b < kNumBodies; ++b) {
    const int n = kTree.body_node[b];
    const RigidBodyParameters& body = kTree.bodies[b];
    const auto Jv = point_jacobian(kTree, kin, n, point_position(kin, n, body.com_m));
    Eigen::Matrix<double, 3, kNumCoordinates> Jw;
    for (int k = 0; k < kNumCoordinates; ++k) {
      const double h = 1e-6;
      Coordinates qp = q, qm = q;
      qp[k] += h;
      qm[k] -= h;
      const Mat3 W = (forward_kinematics(kTree, qp, u).nodes[n].rotation -
                      forward_kinematics(kTree, qm, u).nodes[n].rotation) / (2 * h) *
                     kin.nodes[n].rotation.transpose();
      Jw.col(k) = Vec3(W(2, 1), W(0, 2), W(1, 0));
    }
    const Mat3 I = kin.nodes[n].rotation * body.inertia_kgm2 * kin.nodes[n].rotation.transpose();
    M += body.mass_kg * Jv.transpose() * Jv + Jw.transpose() * I * Jw;
  }
  const CoordinateMatrix M_crba = mass_matrix(kTree, kin);
  EXPECT_LT((M - M_crba).cwiseAbs().maxCoeff(), 1e-9 * M_crba.cwiseAbs().maxCoeff());
}

TEST(Dynamics, KineticEnergyIsHalfTheMassMatrixQuadraticForm) {
  // Body by body (m |v_com|^2 + w . I w) / 2 against u^T M u / 2 from the
  // composite-body pass: both read the world inertias of forward_kinematics.
  std::mt19937 rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    const TreeKinematics kin = forward_kinematics(kTree, q, u);
    const double T = kinetic_energy(kTree, kin);
    EXPECT_GT(T, 0.0);
    EXPECT_NEAR(T, 0.5 * u.dot(mass_matrix(kTree, kin) * u), 1e-12 * T);
  }
}

TEST(Dynamics, VelocityTermsSatisfyLagrangesEquations) {
  // With T = u^T M(q) u / 2, Lagrange gives the velocity-dependent generalized
  // force -(dM/dt u - dT/dq); gravity gives -dV/dq.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 3; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    const double h = 1e-6;
    Coordinates dT_dq;
    CoordinateMatrix M_dot = CoordinateMatrix::Zero();
    for (int k = 0; k < kNumCoordinates; ++k) {
      Coordinates qp = q, qm = q;
      qp[k] += h;
      qm[k] -= h;
      const CoordinateMatrix dM = (mass_at(qp) - mass_at(qm)) / (2 * h);
      dT_dq[k] = 0.5 * u.dot(dM * u);
      M_dot += dM * u[k];
    }
    const Coordinates expected_velocity_terms = -(M_dot * u - dT_dq);
    const Coordinates F_velocity =
        gravity_and_inertia_forces(kTree, forward_kinematics(kTree, q, u), 0.0);
    EXPECT_LT((F_velocity - expected_velocity_terms).cwiseAbs().maxCoeff(),
              1e-6 * std::max(1.0, expected_velocity_terms.cwiseAbs().maxCoeff()));

    const double g = kParams.gravity_mps2;
    const Coordinates F_gravity =
        gravity_and_inertia_forces(kTree, forward_kinematics(kTree, q, Coordinates::Zero()), g);
    for (int k = 0; k < kNumCoordinates; ++k) {
      Coordinates qp = q, qm = q;
      qp[k] += h;
      qm[k] -= h;
      const double dV = (gravity_potential_energy(kTree, forward_kinematics(kTree, qp, u), g) -
                         gravity_potential_energy(kTree, forward_kinematics(kTree, qm, u), g)) / (2 * h);
      EXPECT_NEAR(F_gravity[k], -dV, 1e-7) << "coordinate " << k;
    }
  }
}

TEST(Dynamics, JointTorquesDeriveFromTheirPotentials) {
  std::mt19937 rng(9);
  ModelInputs in = nominal_inputs(kParams);
  in.sharpness_f = 30.0;  // smooth enough for a central difference
  in.steer_ref_rad = {0.1, -0.2, 0.3, 0.0};
  Coordinates q, u;
  testing::random_state(rng, q, u);
  q[coord::steer(2)] = 1.9;  // past the end-stop
  const Coordinates Q = joint_forces(kParams, in, q, Coordinates::Zero());
  const double h = 1e-7;
  for (int k = coord::s_joint(0, 0); k <= coord::steer(3); ++k) {
    Coordinates qp = q, qm = q;
    qp[k] += h;
    qm[k] -= h;
    const double dV = (joint_potential_energy(kParams, in, qp) - joint_potential_energy(kParams, in, qm)) / (2 * h);
    EXPECT_NEAR(Q[k], -dV, 1e-6) << "coordinate " << k;
  }
}

TEST(Dynamics, SStructureTorqueDerivativesMatchFiniteDifferences) {
  const double b = 2e-4, db = 0.3, h = 1e-9;
  const JointTorque t = s_structure_torque(b, db, 1.9, 1e4, 9.91, 0.14);
  const double dtdb = (s_structure_torque(b + h, db, 1.9, 1e4, 9.91, 0.14).torque_Nm -
                       s_structure_torque(b - h, db, 1.9, 1e4, 9.91, 0.14).torque_Nm) / (2 * h);
  EXPECT_NEAR(t.d_angle, dtdb, 1e-5 * std::abs(dtdb));
  EXPECT_DOUBLE_EQ(t.d_rate, -0.14);
  // Far from zero the spring tends to the preload plus the linear part.
  EXPECT_NEAR(s_structure_torque(0.5, 0.0, 1.9, 1e4, 9.91, 0.0).torque_Nm, -1.9 - 9.91 * 0.5, 1e-3);
}

}  // namespace
}  // namespace rover
