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
    const MakkarMuAndDerivative m = makkar_mu_and_derivative(s, friction.gammas, c.friction_tanh);
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
      d.d_position[c] = s_structure_stiffness(q[c], in.preload_Nm[2 * leg + i], in.sharpness_f,
                                              p.s_structure.stiffness_Nm_per_rad);
      d.d_speed[c] = -in.damping_c_q;  // s_structure_torque()'s d_rate
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
  StiffForceJacobian jac;
  stiff_force_jacobian(model, workspace, inputs, q, u, jac.d_speed, jac.d_position, jac.spring_d_position_diagonal);
  return jac;
}

void stiff_force_jacobian(const RoverModel& model, const DynamicsWorkspace& workspace, const ModelInputs& inputs,
                          const Coordinates& q, const Coordinates& u, CoordinateMatrix& d_speed,
                          CoordinateMatrix& d_position, Coordinates& spring_d_position_diagonal) {
  const TreeKinematics& kin = workspace.kinematics;
  const std::array<WheelContacts, kNumLegs>& contacts = workspace.contacts;
  const JointForceDerivatives joints = joint_force_derivatives(model.parameters, inputs, q, u);
  d_speed.setZero();
  d_position.setZero();
  d_speed.diagonal() = joints.d_speed;
  d_position.diagonal() = joints.d_position;
  spring_d_position_diagonal = joints.d_position;
  // A wheel's J_P and dv_P/dq have non-zero columns only for the coordinates
  // on its path to the root (one node per coordinate there): every product is
  // formed on those columns alone (11 of 23), at a size fixed at compile time
  // (the ones past the path length are zero), coefficient by coefficient, and
  // added into D and K there. The path columns are kept transposed (PathRows,
  // one row per coordinate, as kinematic_tree.hpp's path Jacobians give
  // them): then each component is a contiguous column and Eigen forms the
  // products by packets.
  using PathRows = PathJacobian;
  using PathBlock = Eigen::Matrix<double, kMaxTreeDepth, kMaxTreeDepth>;
  using PathVector = Eigen::Matrix<double, kMaxTreeDepth, 1>;
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
    const auto add_on_path = [&](const PathBlock& d_speed_on_path, const PathBlock& d_position_on_path) {
      for (int b = 0; b < path_length; ++b)
        for (int a = 0; a < path_length; ++a) {
          d_speed(path_coordinate[a], path_coordinate[b]) += d_speed_on_path(a, b);
          d_position(path_coordinate[a], path_coordinate[b]) += d_position_on_path(a, b);
        }
    };
    const PathRows centre_jacobian_t = point_jacobian_on_path(model.tree, kin, node, wheel.origin);
    const PathRows omega_jacobian_t = angular_jacobian_on_path(model.tree, kin, node);
    const FrameVelocityPositionDerivativeOnPath frame =
        frame_velocity_position_derivative_on_path(model.tree, kin, node);
    const PathRows& d_origin_velocity_t = frame.d_origin_velocity;
    const PathRows& d_omega_t = frame.d_omega;
    for (int k = 0; k < at_wheel.count; ++k) {
      const ContactPoint& c = at_wheel.points[k];
      if (!(c.normal_force_N > 0.0)) continue;
      const ContactForceDerivatives d =
          contact_force_derivatives(c, model.parameters.contact, model.parameters.friction);
      const Mat3 d_force_d_velocity_t = d.d_force_d_velocity.transpose();
      const Mat3 lever_cross_t = cross_matrix(c.point_m - wheel.origin).transpose();
      // J_P = dv_P/du = J_c - [P - c]x J_omega.
      const PathRows J_t = centre_jacobian_t - omega_jacobian_t.lazyProduct(lever_cross_t);
      const PathRows D_J_t = J_t.lazyProduct(d_force_d_velocity_t);  // (df/dv_P J_P)^T
      // v_P = J_P u changes with q: the frame turns and P slides over the rim
      // (contact_point_turning: dP/dq - dc/dq = T J_omega); the penetration
      // follows the material point (P is the deepest point), dp/dq = -n^T J_P.
      const Mat3 slide_t = (cross_matrix(wheel.omega) *
                            contact_point_turning(c.point_m, wheel.origin, wheel.rotation.col(1)))
                               .transpose();
      const PathRows dv_dq_t = d_origin_velocity_t - d_omega_t.lazyProduct(lever_cross_t) +
                               omega_jacobian_t.lazyProduct(slide_t);
      const PathVector dp_dq_t = -J_t.lazyProduct(c.normal);
      const PathRows df_dq_t = dv_dq_t.lazyProduct(d_force_d_velocity_t) +
                               dp_dq_t.lazyProduct(d.d_force_d_penetration.transpose());
      add_on_path(J_t.lazyProduct(D_J_t.transpose()), J_t.lazyProduct(df_dq_t.transpose()));
      const PathVector spring_diagonal = J_t.lazyProduct(d.d_force_d_penetration).cwiseProduct(dp_dq_t);
      for (int a = 0; a < path_length; ++a) spring_d_position_diagonal[path_coordinate[a]] += spring_diagonal[a];
    }
  }
}

}  // namespace rover
