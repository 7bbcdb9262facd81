// Derivatives of the stiff force elements (core/force_jacobian.cpp)
// against central finite differences of the force laws themselves, evaluated
// through the model: the contact force of one wheel as a function of the
// speeds and of the penetration, the joint torques, and the generalized force
// Jacobians D = dF/du (exact) and K ~ dF/dq (stiff part) of the whole model.
#include "core/force_jacobian.hpp"

#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "core/dynamics.hpp"
#include "core/equations_of_motion.hpp"
#include "core/friction.hpp"
#include "core/friction_synthesis.hpp"
#include "model_fixtures.hpp"

namespace rover {
namespace {

constexpr double kBottomBelowG = 0.2285;  // wheel bottoms below G at q = 0 (docs/model.md §3)

std::vector<Terrain> test_terrains() {
  return {Terrain::flat(), Terrain::from_grid(testing::sampled_grid(
                              -2.0, -2.0, 0.011, 0.013, 365, 310,
                              [](double x, double y) { return 0.003 * x - 0.002 * y; }))};
}

// The force f = F_n n + F_t of contact k of `leg` at (q, u).
Vec3 contact_force(const RoverModel& model, int leg, int k, const Coordinates& q, const Coordinates& u) {
  const TreeKinematics kin = forward_kinematics(model.tree, q, u);
  const ContactPoint& c = wheel_contacts(model, kin)[leg].points[k];
  return c.normal_force_N * c.normal + c.friction_force_N;
}

Coordinates stiff_forces(const RoverModel& model, const ModelInputs& in, const Coordinates& q,
                         const Coordinates& u) {
  const TreeKinematics kin = forward_kinematics(model.tree, q, u);
  return joint_forces(model.parameters, in, q, u) +
         contact_generalized_forces(model, kin, wheel_contacts(model, kin));
}

// Speeds that make every wheel slip at about `slip` m/s (forward rolling
// slower than the chassis moves), plus a little of everything else.
Coordinates slipping_speeds(double slip, std::mt19937& rng) {
  std::uniform_real_distribution<double> small(-0.02, 0.02);
  Coordinates u = Coordinates::Zero();
  for (int i = 0; i < kNumCoordinates; ++i) u[i] = small(rng) * slip;
  u[coord::x] = 0.5;
  for (int leg = 0; leg < kNumLegs; ++leg) u[coord::spin(leg)] = (0.5 - slip) / 0.085;
  u[coord::z] = -0.001;  // sinking: the damper adds to the spring
  return u;
}

TEST(ForceJacobian, ContactForceDerivativesMatchFiniteDifferencesOfTheForceLaw) {
  std::mt19937 rng(7);
  int checked = 0;
  for (const Terrain& terrain : test_terrains()) {
    const RoverModel model = make_rover_model(default_rover_parameters(), terrain);
    // Sliding, slipping through the Stribeck peak (mu_s at v_s = 0.55 mm/s),
    // and at rest, where the derivative is the limit mu'(0) F_n.
    for (const double slip : {0.2, 5e-4, 0.0}) {
      Coordinates q = Coordinates::Zero();
      q[coord::z] = kBottomBelowG - 0.002;
      const Coordinates u = slip > 0.0 ? slipping_speeds(slip, rng) : Coordinates::Zero();
      const TreeKinematics kin = forward_kinematics(model.tree, q, u);
      const auto contacts = wheel_contacts(model, kin);
      for (int leg = 0; leg < kNumLegs; ++leg) {
        ASSERT_EQ(contacts[leg].count, 1);
        const ContactPoint& c = contacts[leg].points[0];
        ASSERT_GT(c.normal_force_N, 1.0);
        const ContactForceDerivatives d =
            contact_force_derivatives(c, model.parameters.contact, model.parameters.friction);
        const auto J = point_jacobian(model.tree, kin, node::wheel(leg), c.point_m);
        // Speeds: v_P = J_P u, so df/du = (df/dv_P) J_P. The step is small
        // against v_s, on which the friction law varies.
        const double du = 1e-8;
        Eigen::Matrix<double, 3, kNumCoordinates> fd;
        for (int i = 0; i < kNumCoordinates; ++i) {
          Coordinates up = u, um = u;
          up[i] += du;
          um[i] -= du;
          fd.col(i) = (contact_force(model, leg, 0, q, up) - contact_force(model, leg, 0, q, um)) / (2.0 * du);
        }
        const Eigen::Matrix<double, 3, kNumCoordinates> analytic = d.d_force_d_velocity * J;
        EXPECT_LT((analytic - fd).norm(), 1e-5 * fd.norm())
            << "slip " << slip << " leg " << leg << "\nanalytic\n" << analytic << "\nfd\n" << fd;
        // Penetration: lifting the chassis by dz moves P rigidly, so on a
        // plane only p changes, by dp = -n_z dz = -(n^T J_P) e_z dz. On a
        // grid, P is found by Brent's method to ~1e-9 m along the rim, which
        // moves v_P and so dp/dt a little: dz is kept well above that.
        const double dz = 1e-6;
        Coordinates qp = q, qm = q;
        qp[coord::z] += dz;
        qm[coord::z] -= dz;
        const Vec3 fd_z = (contact_force(model, leg, 0, qp, u) - contact_force(model, leg, 0, qm, u)) / (2.0 * dz);
        const Vec3 analytic_z = -d.d_force_d_penetration * c.normal.dot(J.col(coord::z));
        EXPECT_LT((analytic_z - fd_z).norm(), 1e-4 * fd_z.norm())
            << "slip " << slip << " leg " << leg << ": " << analytic_z.transpose() << " vs " << fd_z.transpose();
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 2 * 3 * kNumLegs);
}

TEST(ForceJacobian, NoForceNoDerivative) {
  // A wheel being pulled out faster than its spring pushes: F_n clamps at 0.
  const RoverModel model = make_rover_model(default_rover_parameters());
  Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
  q[coord::z] = kBottomBelowG - 1e-4;
  u[coord::z] = 1.0;
  u[coord::x] = 0.3;
  const auto contacts = wheel_contacts(model, forward_kinematics(model.tree, q, u));
  for (const WheelContacts& w : contacts) {
    ASSERT_EQ(w.count, 1);
    ASSERT_EQ(w.points[0].normal_force_N, 0.0);
    const ContactForceDerivatives d =
        contact_force_derivatives(w.points[0], model.parameters.contact, model.parameters.friction);
    EXPECT_EQ(d.d_force_d_velocity, Mat3::Zero());
    EXPECT_EQ(d.d_force_d_penetration, Vec3::Zero());
  }
}

TEST(ForceJacobian, JointForceDerivativesMatchFiniteDifferences) {
  const RoverParameters p = default_rover_parameters();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> speed(-2.0, 2.0), tiny(-3e-4, 3e-4);
  for (int trial = 0; trial < 6; ++trial) {
    ModelInputs in = nominal_inputs(p);
    in.sharpness_f = trial % 2 == 0 ? 1e4 : 1e2;
    for (int leg = 0; leg < kNumLegs; ++leg) {
      in.wheel_speed_ref_radps[leg] = speed(rng);
      in.steer_ref_rad[leg] = 0.3 * speed(rng);
    }
    Coordinates q, u;
    testing::random_state(rng, q, u);
    for (int i = 0; i < 2 * kNumLegs; ++i) q[coord::s_joint(i / 2, i % 2)] = tiny(rng);  // the steep region
    q[coord::steer(0)] = 1.9;   // beyond the end-stop
    q[coord::steer(1)] = -1.8;
    u[coord::spin(2)] = in.wheel_speed_ref_radps[2] + 30.0;  // drive saturated
    for (int i = 0; i < kNumCoordinates; ++i) u[i] *= 3.0;
    const JointForceDerivatives d = joint_force_derivatives(p, in, q, u);
    for (int c = 0; c < kNumCoordinates; ++c) {
      // Steps well inside the narrowest feature: the atan region 1/f.
      const double hq = 1e-9, hu = 1e-7;
      Coordinates qp = q, qm = q, up = u, um = u;
      qp[c] += hq;
      qm[c] -= hq;
      up[c] += hu;
      um[c] -= hu;
      const Coordinates dq = (joint_forces(p, in, qp, u) - joint_forces(p, in, qm, u)) / (2.0 * hq);
      const Coordinates du = (joint_forces(p, in, q, up) - joint_forces(p, in, q, um)) / (2.0 * hu);
      Coordinates expected_q = Coordinates::Zero(), expected_u = Coordinates::Zero();
      expected_q[c] = d.d_position[c];
      expected_u[c] = d.d_speed[c];
      EXPECT_LT((dq - expected_q).cwiseAbs().maxCoeff(), 1e-5 * std::max(1.0, std::abs(dq[c])))
          << "trial " << trial << " coordinate " << kCoordinateNames[c];
      EXPECT_LT((du - expected_u).cwiseAbs().maxCoeff(), 1e-5 * std::max(1.0, std::abs(du[c])))
          << "trial " << trial << " coordinate " << kCoordinateNames[c];
    }
  }
}

// Random states with all four wheels in contact.
struct ContactState {
  Coordinates q, u;
};
ContactState contact_state(std::mt19937& rng, double speed_scale) {
  ContactState s;
  testing::random_state(rng, s.q, s.u);
  s.q[coord::x] *= 0.5;
  s.q[coord::y] *= 0.5;
  s.q[coord::z] = kBottomBelowG - 0.005;
  // Attitude and joints within a few mrad: every wheel stays 2 to 8 mm deep.
  for (int i = coord::yaw; i < kNumCoordinates; ++i) s.q[i] *= 0.01;
  s.u *= speed_scale;
  s.u[coord::z] = -0.002;  // sinking, so no wheel is near the F_n = 0 clamp
  return s;
}

TEST(ForceJacobian, SpeedJacobianIsExact) {
  std::mt19937 rng(11);
  for (const Terrain& terrain : test_terrains()) {
    const RoverModel model = make_rover_model(default_rover_parameters(), terrain);
    const ModelInputs in = nominal_inputs(model.parameters);
    for (int trial = 0; trial < 4; ++trial) {
      const ContactState s = contact_state(rng, 0.1);
      DynamicsWorkspace workspace;
      compute_kinematics(model, workspace, s.q, s.u);
      compute_contacts(model, workspace);
      for (const WheelContacts& w : workspace.contacts) ASSERT_GE(w.count, 1);
      const StiffForceJacobian jac = stiff_force_jacobian(model, workspace, in, s.q, s.u);
      CoordinateMatrix fd;
      const double h = 1e-8;
      for (int i = 0; i < kNumCoordinates; ++i) {
        Coordinates up = s.u, um = s.u;
        up[i] += h;
        um[i] -= h;
        fd.col(i) = (stiff_forces(model, in, s.q, up) - stiff_forces(model, in, s.q, um)) / (2.0 * h);
      }
      EXPECT_LT((jac.d_speed - fd).norm(), 1e-5 * fd.norm()) << "trial " << trial;
    }
  }
}

// K at (q, u) against central differences of the stiff forces. What K leaves
// out, the turning of J_P and n with q under the contact forces, is forces
// times levers no longer than the rover (0.72 m), and K holds all but a few
// percent of dF/dq.
void expect_position_jacobian_has_the_stiff_part(const RoverModel& model, const ModelInputs& in,
                                                 const Coordinates& q, const Coordinates& u, double h,
                                                 const std::string& label) {
  DynamicsWorkspace workspace;
  compute_kinematics(model, workspace, q, u);
  compute_contacts(model, workspace);
  double total_force = 0.0;
  for (const WheelContacts& w : workspace.contacts) total_force += w.total_normal_force_N();
  const StiffForceJacobian jac = stiff_force_jacobian(model, workspace, in, q, u);
  CoordinateMatrix fd;
  for (int i = 0; i < kNumCoordinates; ++i) {
    Coordinates qp = q, qm = q;
    qp[i] += h;
    qm[i] -= h;
    fd.col(i) = (stiff_forces(model, in, qp, u) - stiff_forces(model, in, qm, u)) / (2.0 * h);
  }
  EXPECT_LT((jac.d_position - fd).cwiseAbs().maxCoeff(), total_force * 1.0)
      << label << ": stiffness " << fd.cwiseAbs().maxCoeff();
  EXPECT_LT((jac.d_position - fd).norm(), 0.02 * fd.norm()) << label;
}

TEST(ForceJacobian, PositionJacobianHasTheStiffPartOfTheFiniteDifferences) {
  // At rest: K is the contact and S-structure stiffness.
  std::mt19937 rng(12);
  for (const Terrain& terrain : test_terrains()) {
    const RoverModel model = make_rover_model(default_rover_parameters(), terrain);
    const ModelInputs in = nominal_inputs(model.parameters);
    for (int trial = 0; trial < 4; ++trial) {
      const ContactState s = contact_state(rng, 0.0);
      expect_position_jacobian_has_the_stiff_part(model, in, s.q, s.u, 1e-9, "trial " + std::to_string(trial));
    }
  }
}

// Speeds of a rover that moves (joints at up to 1 rad/s) while its wheels
// roll without slipping: u minus its least-norm part that makes the contact
// points of (q, u) slip.
Coordinates rolling_speeds(const RoverModel& model, const Coordinates& q, Coordinates u) {
  const TreeKinematics kin = forward_kinematics(model.tree, q, u);
  const auto contacts = wheel_contacts(model, kin);
  Eigen::Matrix<double, Eigen::Dynamic, kNumCoordinates> slip_rows(0, kNumCoordinates);
  for (int leg = 0; leg < kNumLegs; ++leg)
    for (int k = 0; k < contacts[leg].count; ++k) {
      const ContactPoint& c = contacts[leg].points[k];
      const Eigen::Matrix<double, 3, kNumCoordinates> J =
          point_jacobian(model.tree, kin, node::wheel(leg), c.point_m);
      // Two tangent directions.
      const Vec3 t1 = c.normal.unitOrthogonal(), t2 = c.normal.cross(t1);
      const Eigen::Index rows = slip_rows.rows();
      slip_rows.conservativeResize(rows + 2, Eigen::NoChange);
      slip_rows.row(rows) = t1.transpose() * J;
      slip_rows.row(rows + 1) = t2.transpose() * J;
    }
  return u - slip_rows.transpose() * (slip_rows * slip_rows.transpose()).ldlt().solve(slip_rows * u);
}

TEST(ForceJacobian, PositionJacobianHasTheStiffPartWhileTheWheelsRoll) {
  // As q turns a rolling wheel, its slip velocity turns with it, and the
  // stuck friction (mu'(0) F_n, ~1e4 N s/m, 100 times more with v_s 100 times
  // smaller) makes that a stiffness of ~mu'(0) F_n |u| per rad that K must
  // hold (force_jacobian.hpp). On flat ground, where P is exactly the lowest
  // rim point: on a height grid P snaps to grid lines, which the slip of a
  // moving wheel would feel in a finite difference.
  std::mt19937 rng(13);
  for (const double v_s_scale : {1.0, 0.01}) {
    RoverParameters p = default_rover_parameters();
    p.friction = with_friction_speeds_scaled(p.friction, v_s_scale);
    const RoverModel model = make_rover_model(p, Terrain::flat());
    const ModelInputs in = nominal_inputs(model.parameters);
    for (int trial = 0; trial < 4; ++trial) {
      ContactState s = contact_state(rng, 1.0);
      s.u = rolling_speeds(model, s.q, s.u);
      s.u[coord::z] -= 0.002;  // sinking, away from the F_n = 0 clamp
      expect_position_jacobian_has_the_stiff_part(
          model, in, s.q, s.u, 1e-10, "v_s x " + std::to_string(v_s_scale) + " trial " + std::to_string(trial));
    }
  }
}

}  // namespace
}  // namespace rover
