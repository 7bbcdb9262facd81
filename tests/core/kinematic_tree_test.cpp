// Kinematics of the tree (core/kinematic_tree.cpp): docs/model.md §3 geometry,
// Jacobians and bias accelerations against finite differences.
#include "core/kinematic_tree.hpp"

#include <gtest/gtest.h>

#include "model_fixtures.hpp"

namespace rover {
namespace {

const KinematicTree kTree = build_kinematic_tree(default_rover_parameters());

TEST(KinematicTree, WheelCentresAtZeroMatchModelGeometry) {
  const TreeKinematics kin = forward_kinematics(kTree, Coordinates::Zero(), Coordinates::Zero());
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec3 c = kin.nodes[node::wheel(leg)].origin;
    EXPECT_NEAR(c.x(), leg_sign_x(leg) * 0.360, 1e-12) << "leg " << leg;
    EXPECT_NEAR(c.y(), leg_sign_y(leg) * 0.2215, 1e-12) << "leg " << leg;
    EXPECT_NEAR(c.z(), -0.1435, 1e-12) << "leg " << leg;
  }
  const Vec3 fl = kin.nodes[node::wheel(0)].origin, fr = kin.nodes[node::wheel(1)].origin,
             rl = kin.nodes[node::wheel(2)].origin;
  EXPECT_NEAR(fl.x() - rl.x(), 0.720, 1e-12);  // wheelbase L (Table 1)
  EXPECT_NEAR(fl.y() - fr.y(), 0.443, 1e-12);  // track W (Table 1)
  EXPECT_NEAR(-fl.z() + default_rover_parameters().geometry.wheel_radius_m, 0.2285, 1e-12);
  EXPECT_NEAR(kTree.total_mass_kg, 4.427, 1e-12);
}

TEST(KinematicTree, PositiveSJointAngleLiftsTheWheel) {
  for (int leg = 0; leg < kNumLegs; ++leg)
    for (int i = 0; i < 2; ++i) {
      Coordinates q = Coordinates::Zero();
      q[coord::s_joint(leg, i)] = 0.1;
      const TreeKinematics kin = forward_kinematics(kTree, q, Coordinates::Zero());
      EXPECT_GT(kin.nodes[node::wheel(leg)].origin.z(), -0.1435 + 0.005) << leg << "," << i;
    }
}

TEST(KinematicTree, BogieCouplingRotatesSidesOppositely) {
  Coordinates q = Coordinates::Zero();
  q[coord::bogie] = 0.1;
  const TreeKinematics kin = forward_kinematics(kTree, q, Coordinates::Zero());
  // Right bogie Ry(+phi) lowers its front; the left one, Ry(-phi), raises it.
  EXPECT_LT(kin.nodes[node::wheel(1)].origin.z(), -0.1435 - 0.01);
  EXPECT_GT(kin.nodes[node::wheel(0)].origin.z(), -0.1435 + 0.01);
  EXPECT_NEAR(kin.nodes[node::wheel(0)].origin.z() + kin.nodes[node::wheel(1)].origin.z(),
              kin.nodes[node::wheel(2)].origin.z() + kin.nodes[node::wheel(3)].origin.z(), 1e-12);
}

TEST(KinematicTree, BodyMassDistributionIsTheBodyFramesTurnedToWorldAxes) {
  std::mt19937 rng(4);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  const TreeKinematics kin = forward_kinematics(kTree, q, u);
  for (int b = 0; b < kNumBodies; ++b) {
    const Mat3& R = kin.nodes[kTree.body_node[b]].rotation;
    const RigidBodyParameters& body = kTree.bodies[b];
    const BodyKinematics& world = kin.bodies[b];
    EXPECT_LT((world.com_offset - R * body.com_m).norm(), 1e-15) << "body " << b;
    const Mat3 expected = R * body.inertia_kgm2 * R.transpose();
    EXPECT_LT((world.inertia - expected).norm(), 1e-15 * expected.norm()) << "body " << b;
    EXPECT_EQ(world.inertia, world.inertia.transpose()) << "body " << b;
    // Rotation keeps the principal moments; the trace is their sum.
    EXPECT_NEAR(world.inertia.trace(), body.inertia_kgm2.trace(), 1e-15) << "body " << b;
  }
}

TEST(KinematicTree, AGeneralAxisMovesLikeItsElementaryEquivalent) {
  // Turning by -q about -e_y is turning by q about e_y, and sliding by -q
  // along -e_y is sliding by q along e_y. With those axes forward_kinematics
  // leaves its elementary-axis shortcuts for the general path (parent
  // rotation times axis, Eigen::AngleAxis) and must give the same motion.
  KinematicTree flipped = kTree;
  for (const int n : {1, node::bogie_left, node::wheel(0), node::wheel(3)}) {
    flipped.nodes[n].axis = -flipped.nodes[n].axis;
    flipped.nodes[n].sign = -flipped.nodes[n].sign;
  }
  std::mt19937 rng(6);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  const TreeKinematics a = forward_kinematics(kTree, q, u), b = forward_kinematics(flipped, q, u);
  const double tol = 1e-14;
  for (int n = 0; n < kNumTreeNodes; ++n) {
    const NodeKinematics &x = a.nodes[n], &y = b.nodes[n];
    EXPECT_LT((x.rotation - y.rotation).norm(), tol) << "node " << n;
    EXPECT_LT((x.origin - y.origin).norm(), tol) << "node " << n;
    EXPECT_LT((x.omega - y.omega).norm(), tol) << "node " << n;
    EXPECT_LT((x.velocity - y.velocity).norm(), tol) << "node " << n;
    EXPECT_LT((x.alpha_bias - y.alpha_bias).norm(), tol) << "node " << n;
    EXPECT_LT((x.accel_bias - y.accel_bias).norm(), tol) << "node " << n;
    EXPECT_LT((x.motion_omega - y.motion_omega).norm(), tol) << "node " << n;
    EXPECT_LT((x.motion_velocity - y.motion_velocity).norm(), tol) << "node " << n;
  }
  for (int body = 0; body < kNumBodies; ++body)
    EXPECT_LT((a.bodies[body].inertia - b.bodies[body].inertia).norm(), tol) << "body " << body;
}

TEST(KinematicTree, PointJacobianEqualsFiniteDifferences) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 5; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    for (int n : {node::chassis, node::bogie_right, node::module2(2), node::wheel(1), node::wheel(3)}) {
      const Vec3 local(0.013, -0.021, 0.034);
      const TreeKinematics kin = forward_kinematics(kTree, q, u);
      const auto J = point_jacobian(kTree, kin, n, point_position(kin, n, local));
      for (int k = 0; k < kNumCoordinates; ++k) {
        const double h = 1e-6;
        Coordinates qp = q, qm = q;
        qp[k] += h;
        qm[k] -= h;
        const Vec3 fd = (point_position(forward_kinematics(kTree, qp, u), n, local) -
                         point_position(forward_kinematics(kTree, qm, u), n, local)) / (2 * h);
        EXPECT_LT((J.col(k) - fd).norm(), 1e-8) << "node " << n << " coordinate " << k;
      }
      // v_P = J u.
      const Vec3 p = point_position(kin, n, local);
      EXPECT_LT((point_velocity(kin, n, p) - J * u).norm(), 1e-12);
    }
  }
}

TEST(KinematicTree, AngularVelocityEqualsRotationRate) {
  std::mt19937 rng(11);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  const double h = 1e-6;
  const TreeKinematics kin = forward_kinematics(kTree, q, u);
  const TreeKinematics kp = forward_kinematics(kTree, q + h * u, u);
  const TreeKinematics km = forward_kinematics(kTree, q - h * u, u);
  for (int n = 0; n < kNumTreeNodes; ++n) {
    const Mat3 Rdot = (kp.nodes[n].rotation - km.nodes[n].rotation) / (2 * h);
    const Mat3 W = Rdot * kin.nodes[n].rotation.transpose();  // skew(omega)
    const Vec3 omega(W(2, 1), W(0, 2), W(1, 0));
    EXPECT_LT((omega - kin.nodes[n].omega).norm(), 1e-8) << "node " << n;
  }
}

TEST(KinematicTree, PoseAndVelocityAloneAreThoseOfTheFullKinematics) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 20; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    const TreeKinematics full = forward_kinematics(kTree, q, u);
    TreeKinematics lean = forward_kinematics(kTree, Coordinates::Zero(), Coordinates::Zero());
    forward_pose_and_velocity(kTree, q, u, lean);
    EXPECT_EQ(lean.reference, full.reference);
    for (int n = 0; n < kNumTreeNodes; ++n) {
      const NodeKinematics &a = lean.nodes[n], &b = full.nodes[n];
      EXPECT_EQ(a.rotation, b.rotation) << "node " << n;
      EXPECT_EQ(a.origin, b.origin) << "node " << n;
      EXPECT_EQ(a.axis, b.axis) << "node " << n;
      EXPECT_EQ(a.omega, b.omega) << "node " << n;
      EXPECT_EQ(a.velocity, b.velocity) << "node " << n;
    }
  }
}

TEST(KinematicTree, BiasAccelerationIsTheDerivativeOfVelocityAlongTheMotion) {
  std::mt19937 rng(3);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  const double h = 1e-6;
  const TreeKinematics kin = forward_kinematics(kTree, q, u);
  const TreeKinematics kp = forward_kinematics(kTree, q + h * u, u);
  const TreeKinematics km = forward_kinematics(kTree, q - h * u, u);
  for (int n = 0; n < kNumTreeNodes; ++n) {
    const Vec3 a = (kp.nodes[n].velocity - km.nodes[n].velocity) / (2 * h);
    const Vec3 alpha = (kp.nodes[n].omega - km.nodes[n].omega) / (2 * h);
    EXPECT_LT((a - kin.nodes[n].accel_bias).norm(), 1e-6) << "node " << n;
    EXPECT_LT((alpha - kin.nodes[n].alpha_bias).norm(), 1e-6) << "node " << n;
  }
}

TEST(KinematicTree, AngularJacobianGivesTheAngularVelocity) {
  std::mt19937 rng(5);
  Coordinates q, u;
  testing::random_state(rng, q, u);
  const TreeKinematics kin = forward_kinematics(kTree, q, u);
  for (int n = 0; n < kNumTreeNodes; ++n)
    EXPECT_LT((angular_jacobian(kTree, kin, n) * u - kin.nodes[n].omega).norm(), 1e-12) << "node " << n;
}

TEST(KinematicTree, FrameVelocityPositionDerivativeEqualsFiniteDifferences) {
  // d v_o/dq and d omega/dq at fixed u, through every kind of joint: the
  // floating base (translations and rotations), the bogie coupling (two
  // nodes on one coordinate), the legs, the steering and the wheel spin.
  std::mt19937 rng(17);
  for (int trial = 0; trial < 4; ++trial) {
    Coordinates q, u;
    testing::random_state(rng, q, u);
    u *= 3.0;
    const TreeKinematics kin = forward_kinematics(kTree, q, u);
    for (int n : {node::chassis, node::bogie_left, node::module2(0), node::hub(2), node::wheel(1),
                  node::wheel(3)}) {
      const FrameVelocityPositionDerivative d = frame_velocity_position_derivative(kTree, kin, n);
      for (int k = 0; k < kNumCoordinates; ++k) {
        const double h = 1e-6;
        Coordinates qp = q, qm = q;
        qp[k] += h;
        qm[k] -= h;
        const TreeKinematics kp = forward_kinematics(kTree, qp, u), km = forward_kinematics(kTree, qm, u);
        const Vec3 dv = (kp.nodes[n].velocity - km.nodes[n].velocity) / (2 * h);
        const Vec3 dw = (kp.nodes[n].omega - km.nodes[n].omega) / (2 * h);
        EXPECT_LT((d.d_origin_velocity.col(k) - dv).norm(), 1e-7 * (1.0 + dv.norm()))
            << "node " << n << " coordinate " << k;
        EXPECT_LT((d.d_omega.col(k) - dw).norm(), 1e-7 * (1.0 + dw.norm())) << "node " << n << " coordinate " << k;
      }
    }
  }
}

}  // namespace
}  // namespace rover
