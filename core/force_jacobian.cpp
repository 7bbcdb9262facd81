// Derivatives of the stiff applied forces (see force_jacobian.hpp).
#include "core/force_jacobian.hpp"

#include <array>
#include <cmath>

#include "core/actuators.hpp"
#include "core/friction.hpp"
#include "core/s_structure.hpp"

namespace rover {

ContactForceDerivatives contact_force_derivatives(const ContactPoint& c,
                                                  const ContactParameters& parameters,
                                                  const FrictionParameters& friction) {
  ContactForceDerivatives out;
  if (!(c.normal_force_N > 0.0)) return out;  // clamped: no force nearby
  const Vec3& n = c.normal;
  const double p = std::max(c.penetration_m, 0.0);
  // F_n = k p^sigma + c_g dp/dt with dp/dt = -v_P . n.
  const double dFn_dp =
      p > 0.0 ? parameters.stiffness_k_g * parameters.exponent_sigma *
                    std::pow(p, parameters.exponent_sigma - 1.0)
              : 0.0;
  // F_t = -mu(s) F_n e with s = |v_t|, e = v_t / s, v_t = (I - n n^T) v_P.
  // d(mu(s) e)/dv_t = mu'(s) e e^T + (mu(s) / s) (P - e e^T), P = I - n n^T;
  // as s -> 0 both mu' and mu/s tend to mu'(0), so it tends to mu'(0) P.
  const Mat3 tangent = Mat3::Identity() - n * n.transpose();
  const double s = c.slip_velocity_mps.norm();
  Mat3 friction_gain;  // d(mu e)/dv_P
  Vec3 mu_e = Vec3::Zero();
  if (s > 0.0) {
    const Vec3 e = c.slip_velocity_mps / s;
    const MakkarMuAndDerivative m = makkar_mu_and_derivative(s, friction.gammas);
    const double mu_over_s = m.mu / s;
    friction_gain = m.d_mu_d_v * e * e.transpose() + mu_over_s * (tangent - e * e.transpose());
    mu_e = m.mu * e;
  } else {
    friction_gain = makkar_mu_derivative(0.0, friction.gammas) * tangent;
  }
  // f = F_n (n - mu e): df/dF_n = n - mu e, dF_n/dv_P = -c_g n^T.
  const Vec3 d_force_d_normal_force = n - mu_e;
  out.d_force_d_velocity = -parameters.damping_c_g * d_force_d_normal_force * n.transpose() -
                           c.normal_force_N * friction_gain;
  out.d_force_d_penetration = dFn_dp * d_force_d_normal_force;
  return out;
}

JointForceDerivatives joint_force_derivatives(const RoverParameters& p, const ModelInputs& in,
                                              const Coordinates& q, const Coordinates& u) {
  JointForceDerivatives d;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    for (int i = 0; i < 2; ++i) {
      const int c = coord::s_joint(leg, i);
      const JointTorque t = s_structure_torque(q[c], u[c], in.preload_Nm[2 * leg + i],
                                               in.sharpness_f, p.s_structure.stiffness_Nm_per_rad,
                                               in.damping_c_q);
      d.d_position[c] = t.d_angle;
      d.d_speed[c] = t.d_rate;
    }
    const int s = coord::steer(leg);
    const JointTorque steer = steering_torque(q[s], u[s], in.steer_ref_rad[leg], p.steering);
    d.d_position[s] = steer.d_angle;
    d.d_speed[s] = steer.d_rate;
    const int w = coord::spin(leg);
    d.d_speed[w] = drive_torque(u[w], in.wheel_speed_ref_radps[leg], p.drive).d_rate;
  }
  return d;
}

StiffForceJacobian stiff_force_jacobian(const RoverModel& model, const DynamicsWorkspace& workspace,
                                        const ModelInputs& inputs, const Coordinates& q,
                                        const Coordinates& u) {
  const TreeKinematics& kin = workspace.kinematics;
  const std::array<WheelContacts, kNumLegs>& contacts = workspace.contacts;
  StiffForceJacobian jac;
  const JointForceDerivatives joints = joint_force_derivatives(model.parameters, inputs, q, u);
  jac.d_speed.diagonal() = joints.d_speed;
  jac.d_position.diagonal() = joints.d_position;
  jac.spring_d_position_diagonal = joints.d_position;
  using Columns = Eigen::Matrix<double, 3, kNumCoordinates>;
  // A wheel's J_P and dv_P/dq have non-zero columns only for the coordinates
  // on its path to the root (one node per coordinate there): every product is
  // formed on those columns alone (11 of 23), at a size fixed at compile time
  // (the columns past the path length are zero), coefficient by coefficient,
  // and added into D and K there.
  using PathColumns = Eigen::Matrix<double, 3, kMaxTreeDepth>;
  using PathBlock = Eigen::Matrix<double, kMaxTreeDepth, kMaxTreeDepth>;
  using PathRow = Eigen::Matrix<double, 1, kMaxTreeDepth>;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const WheelContacts& at_wheel = contacts[leg];
    bool pushing = false;
    for (int k = 0; k < at_wheel.count; ++k) pushing |= at_wheel.points[k].normal_force_N > 0.0;
    if (!pushing) continue;
    const int node = node::wheel(leg);
    const NodeKinematics& wheel = kin.nodes[node];
    const int path_length = model.tree.path_length[node];
    std::array<int, kMaxTreeDepth> path_coordinate{};
    for (int a = 0; a < path_length; ++a) path_coordinate[a] = model.tree.nodes[model.tree.path[node][a]].coordinate;
    const auto on_path = [&](const Columns& full) {
      PathColumns compact = PathColumns::Zero();
      for (int a = 0; a < path_length; ++a) compact.col(a) = full.col(path_coordinate[a]);
      return compact;
    };
    const auto add_on_path = [&](const PathBlock& d_speed, const PathBlock& d_position) {
      for (int b = 0; b < path_length; ++b)
        for (int a = 0; a < path_length; ++a) {
          jac.d_speed(path_coordinate[a], path_coordinate[b]) += d_speed(a, b);
          jac.d_position(path_coordinate[a], path_coordinate[b]) += d_position(a, b);
        }
    };
    const PathColumns centre_jacobian = on_path(point_jacobian(model.tree, kin, node, wheel.origin));
    const PathColumns omega_jacobian = on_path(angular_jacobian(model.tree, kin, node));
    const FrameVelocityPositionDerivative frame = frame_velocity_position_derivative(model.tree, kin, node);
    const PathColumns d_origin_velocity = on_path(frame.d_origin_velocity);
    const PathColumns d_omega = on_path(frame.d_omega);
    for (int k = 0; k < at_wheel.count; ++k) {
      const ContactPoint& c = at_wheel.points[k];
      if (!(c.normal_force_N > 0.0)) continue;
      const ContactForceDerivatives d =
          contact_force_derivatives(c, model.parameters.contact, model.parameters.friction);
      const Mat3 lever_cross = cross_matrix(c.point_m - wheel.origin);
      const PathColumns J = centre_jacobian - lever_cross.lazyProduct(omega_jacobian);  // J_P = dv_P/du
      const PathBlock J_transpose_D_J = J.transpose().lazyProduct(d.d_force_d_velocity.lazyProduct(J));
      // v_P = J_P u changes with q: the frame turns and P slides over the rim
      // (contact_point_turning: dP/dq - dc/dq = T J_omega); the penetration
      // follows the material point (P is the deepest point), dp/dq = -n^T J_P.
      const Mat3 slide = cross_matrix(wheel.omega) *
                         contact_point_turning(c.point_m, wheel.origin, wheel.rotation.col(1));
      const PathColumns dv_dq = d_origin_velocity - lever_cross.lazyProduct(d_omega) +
                                slide.lazyProduct(omega_jacobian);
      const PathRow dp_dq = -c.normal.transpose().lazyProduct(J);
      const PathColumns df_dq =
          d.d_force_d_velocity.lazyProduct(dv_dq) + d.d_force_d_penetration.lazyProduct(dp_dq);
      add_on_path(J_transpose_D_J, J.transpose().lazyProduct(df_dq));
      const PathRow spring_diagonal =
          (d.d_force_d_penetration.transpose().lazyProduct(J)).cwiseProduct(dp_dq);
      for (int a = 0; a < path_length; ++a) jac.spring_d_position_diagonal[path_coordinate[a]] += spring_diagonal[a];
    }
  }
  return jac;
}

}  // namespace rover
