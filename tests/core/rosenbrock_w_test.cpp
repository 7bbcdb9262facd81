// The Rosenbrock-W step ROS34PW2 (core/rosenbrock_w.hpp) on small mechanical
// systems with known behaviour: third order with the exact Jacobian and with
// wrong ones (the W-method property the rover integrator relies on), for a
// configuration-dependent mass matrix and a time-dependent force; L-stability
// on an infinitely stiff spring; exact steps for polynomial motions. The
// fourth-order RODAS4 on the same machinery: order 4 with the exact Jacobian
// of an autonomous system, less with a wrong one (it is not a W-method), an
// order-3 error estimate, and L-stability.
#include "core/rosenbrock_w.hpp"

#include <cmath>
#include <utility>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

namespace rover {
namespace {

using Vec2 = Eigen::Matrix<double, 2, 1>;
using Mat2 = Eigen::Matrix<double, 2, 2>;

// A double-pendulum-like system: M(q) couples the two coordinates through
// cos(q0 - q1); the forces are non-linear in q and u and depend on t.
Mat2 pendulum_mass(const Vec2& q) {
  Mat2 m;
  m << 2.0, std::cos(q[0] - q[1]), std::cos(q[0] - q[1]), 1.0;
  return m;
}
Vec2 pendulum_force(double t, const Vec2& q, const Vec2& u) {
  return {-std::sin(q[0]) - q[0] * q[0] * q[0] - 0.3 * u[0] + 0.5 * std::cos(3.0 * t),
          -std::sin(q[1]) - 0.1 * u[1] * u[1] * u[1] + std::sin(q[0] - q[1]) * u[0] * u[0]};
}
Vec2 pendulum_acceleration(double t, const Vec2& q, const Vec2& u) {
  return pendulum_mass(q).llt().solve(pendulum_force(t, q, u));
}

enum class JacobianKind { kExact, kZero, kWrong };

MechanicalLinearization<2> linearize(double t, const Vec2& q, const Vec2& u, JacobianKind kind) {
  MechanicalLinearization<2> lin;
  lin.mass = pendulum_mass(q);
  lin.force = pendulum_force(t, q, u);
  if (kind == JacobianKind::kExact) {
    const double h = 1e-7;
    for (int j = 0; j < 2; ++j) {
      const Vec2 d = h * Vec2::Unit(j);
      lin.d_force_d_position.col(j) = (pendulum_force(t, q + d, u) - pendulum_force(t, q - d, u)) / (2 * h);
      lin.d_force_d_speed.col(j) = (pendulum_force(t, q, u + d) - pendulum_force(t, q, u - d)) / (2 * h);
    }
  } else if (kind == JacobianKind::kWrong) {
    lin.d_force_d_position << -40.0, 3.0, 1.0, -20.0;
    lin.d_force_d_speed << -7.0, 0.0, 2.0, -1.0;
  }
  return lin;
}

// Max-norm error at t = 2 s of n fixed steps against a converged solution.
double global_error(int n, JacobianKind kind, const Vec2& q_ref, const Vec2& u_ref) {
  Vec2 q(0.5, -0.3), u(0.1, 0.2);
  const double h = 2.0 / n;
  for (int k = 0; k < n; ++k) {
    const double t = k * h;
    const auto step = ros34pw2_step<2>(linearize(t, q, u, kind), t, q, u, h, pendulum_acceleration);
    q = step.q;
    u = step.u;
  }
  return std::max((q - q_ref).cwiseAbs().maxCoeff(), (u - u_ref).cwiseAbs().maxCoeff());
}

TEST(RosenbrockW, ThirdOrderWithAnyJacobian) {
  // Reference: 1280 steps with the exact Jacobian (error ~1e-11).
  Vec2 q(0.5, -0.3), u(0.1, 0.2);
  const int n_ref = 1280;
  for (int k = 0; k < n_ref; ++k) {
    const double h = 2.0 / n_ref, t = k * h;
    const auto step = ros34pw2_step<2>(linearize(t, q, u, JacobianKind::kExact), t, q, u, h,
                                       pendulum_acceleration);
    q = step.q;
    u = step.u;
  }
  for (const JacobianKind kind : {JacobianKind::kExact, JacobianKind::kZero, JacobianKind::kWrong}) {
    const double e80 = global_error(80, kind, q, u), e160 = global_error(160, kind, q, u);
    const double order = std::log2(e80 / e160);
    EXPECT_GT(order, 2.7) << "Jacobian kind " << static_cast<int>(kind) << ": errors " << e80 << ", " << e160;
    EXPECT_LT(order, 3.3) << "Jacobian kind " << static_cast<int>(kind);
  }
}

TEST(RosenbrockW, ErrorEstimateFallsAsTheCubeOfTheStep) {
  // The embedded solution is of order 2: the local error estimate falls as h^3.
  const Vec2 q(0.5, -0.3), u(0.1, 0.2);
  const auto lin = linearize(0.0, q, u, JacobianKind::kExact);
  auto estimate = [&](double h) {
    const auto s = ros34pw2_step<2>(lin, 0.0, q, u, h, pendulum_acceleration);
    return std::max(s.error_q.cwiseAbs().maxCoeff(), s.error_u.cwiseAbs().maxCoeff());
  };
  const double order = std::log2(estimate(0.02) / estimate(0.01));
  EXPECT_NEAR(order, 3.0, 0.2);
}

TEST(RosenbrockW, StiffSpringIsDampedInOneStep) {
  // m q'' = -k q - c q' with k h^2 = 1e10: an L-stable method leaves nothing
  // of the unresolved oscillation (R(inf) = 0), where an explicit method
  // would blow up and a merely A-stable one would keep a fraction of it.
  MechanicalLinearization<1> lin;
  const double m = 1.0, k = 1e14, c = 1.0, h = 1e-2;
  Eigen::Matrix<double, 1, 1> q, u;
  q << 1e-3;
  u << 0.0;
  lin.mass << m;
  lin.force << -k * q[0];
  lin.d_force_d_position << -k;
  lin.d_force_d_speed << -c;
  auto acceleration = [&](double, const Eigen::Matrix<double, 1, 1>& qq, const Eigen::Matrix<double, 1, 1>& uu) {
    return Eigen::Matrix<double, 1, 1>((-k * qq[0] - c * uu[0]) / m);
  };
  const auto step = ros34pw2_step<1>(lin, 0.0, q, u, h, acceleration);
  // The amplitude (q, u / omega) after one step, omega h = 1e5: the
  // stability function falls off as 1 / (omega h) at infinity.
  const double omega = std::sqrt(k / m);
  EXPECT_LT(std::abs(step.q[0]), 1e-4 * std::abs(q[0]));
  EXPECT_LT(std::abs(step.u[0]) / omega, 1e-4 * std::abs(q[0]));
}

TEST(RosenbrockW, ExactForUniformAccelerationAtAnyStep) {
  // Free fall in a time-dependent field a(t) = g0 + g1 t: q is a cubic in t,
  // which a third-order method integrates exactly, whatever the steps (the
  // stages must be taken at their times t + alpha_i h for that).
  const double g0 = -9.81, g1 = 3.0;
  auto acceleration = [&](double t, const Eigen::Matrix<double, 1, 1>&, const Eigen::Matrix<double, 1, 1>&) {
    return Eigen::Matrix<double, 1, 1>(g0 + g1 * t);
  };
  {
    Eigen::Matrix<double, 1, 1> q, u;
    q << 2.0;
    u << 0.5;
    double t = 0.0;
    for (const double h : {0.1, 0.37, 0.05}) {
      MechanicalLinearization<1> lin;
      lin.mass << 2.0;
      lin.force << 2.0 * (g0 + g1 * t);
      const auto step = ros34pw2_step<1>(lin, t, q, u, h, [&](double s, const auto& a, const auto& b) {
        return acceleration(s, a, b);
      });
      q = step.q;
      u = step.u;
      t += h;
    }
    EXPECT_NEAR(q[0], 2.0 + 0.5 * t + g0 * t * t / 2 + g1 * t * t * t / 6, 1e-12);
    EXPECT_NEAR(u[0], 0.5 + g0 * t + g1 * t * t / 2, 1e-12);
  }
}

// An autonomous system with a constant mass matrix and forces non-linear in
// q and u: there [0, I; M^{-1} K, M^{-1} D] with K = dF/dq and D = dF/du is
// the exact Jacobian of dx/dt, which a classical Rosenbrock method needs.
Mat2 constant_mass() {
  Mat2 m;
  m << 2.0, 0.6, 0.6, 1.0;
  return m;
}
Vec2 autonomous_force(const Vec2& q, const Vec2& u) {
  return {-std::sin(q[0]) - 4.0 * q[0] * q[0] * q[0] - 0.3 * u[0] + std::sin(q[1] - q[0]),
          -2.0 * q[1] - 0.1 * u[1] * u[1] * u[1] + std::cos(q[0]) * u[0]};
}
Vec2 autonomous_acceleration(double, const Vec2& q, const Vec2& u) {
  return constant_mass().llt().solve(autonomous_force(q, u));
}

MechanicalLinearization<2> linearize_autonomous(const Vec2& q, const Vec2& u, JacobianKind kind) {
  MechanicalLinearization<2> lin;
  lin.mass = constant_mass();
  lin.force = autonomous_force(q, u);
  if (kind == JacobianKind::kExact) {
    const double d = 1e-6;
    for (int j = 0; j < 2; ++j) {
      const Vec2 e = d * Vec2::Unit(j);
      lin.d_force_d_position.col(j) = (autonomous_force(q + e, u) - autonomous_force(q - e, u)) / (2 * d);
      lin.d_force_d_speed.col(j) = (autonomous_force(q, u + e) - autonomous_force(q, u - e)) / (2 * d);
    }
  } else if (kind == JacobianKind::kWrong) {
    lin.d_force_d_position << -40.0, 3.0, 1.0, -20.0;
    lin.d_force_d_speed << -7.0, 0.0, 2.0, -1.0;
  }
  return lin;
}

// The state at t = 2 s after n equal RODAS4 steps from a fixed start.
std::pair<Vec2, Vec2> rodas4_solution(int n, JacobianKind kind) {
  Vec2 q(0.5, -0.3), u(0.1, 0.2);
  const double h = 2.0 / n;
  for (int k = 0; k < n; ++k) {
    const auto step = rosenbrock_step(kRodas4, linearize_autonomous(q, u, kind), k * h, q, u, h,
                                      autonomous_acceleration);
    q = step.q;
    u = step.u;
  }
  return {q, u};
}

double max_difference(const std::pair<Vec2, Vec2>& a, const std::pair<Vec2, Vec2>& b) {
  return std::max((a.first - b.first).cwiseAbs().maxCoeff(), (a.second - b.second).cwiseAbs().maxCoeff());
}

TEST(Rodas4, FourthOrderWithTheExactJacobian) {
  const auto reference = rodas4_solution(2560, JacobianKind::kExact);
  const double e20 = max_difference(rodas4_solution(20, JacobianKind::kExact), reference);
  const double e40 = max_difference(rodas4_solution(40, JacobianKind::kExact), reference);
  const double order = std::log2(e20 / e40);
  EXPECT_GT(order, 3.7) << "errors " << e20 << ", " << e40;
  EXPECT_LT(order, 4.5) << "errors " << e20 << ", " << e40;
}

TEST(Rodas4, LosesItsOrderWithAWrongJacobian) {
  // Not a W-method: with a matrix other than the Jacobian the order-4
  // conditions fail (ROS34PW2 keeps its order 3 there, above).
  const auto reference = rodas4_solution(2560, JacobianKind::kExact);
  const double e40 = max_difference(rodas4_solution(40, JacobianKind::kWrong), reference);
  const double e80 = max_difference(rodas4_solution(80, JacobianKind::kWrong), reference);
  EXPECT_LT(std::log2(e40 / e80), 3.5) << "errors " << e40 << ", " << e80;
}

TEST(Rodas4, ErrorEstimateFallsAsTheFourthPowerOfTheStep) {
  // The embedded solution is of order 3: the local error estimate falls as h^4.
  const Vec2 q(0.5, -0.3), u(0.1, 0.2);
  const auto lin = linearize_autonomous(q, u, JacobianKind::kExact);
  auto estimate = [&](double h) {
    const auto s = rosenbrock_step(kRodas4, lin, 0.0, q, u, h, autonomous_acceleration);
    return std::max(s.error_q.cwiseAbs().maxCoeff(), s.error_u.cwiseAbs().maxCoeff());
  };
  EXPECT_NEAR(std::log2(estimate(0.02) / estimate(0.01)), 4.0, 0.25);
}

TEST(Rodas4, StiffSpringIsDampedInOneStep) {
  // As for ROS34PW2 above: RODAS4 is L-stable and stiffly accurate.
  MechanicalLinearization<1> lin;
  const double m = 1.0, k = 1e14, c = 1.0, h = 1e-2;
  Eigen::Matrix<double, 1, 1> q, u;
  q << 1e-3;
  u << 0.0;
  lin.mass << m;
  lin.force << -k * q[0];
  lin.d_force_d_position << -k;
  lin.d_force_d_speed << -c;
  auto acceleration = [&](double, const Eigen::Matrix<double, 1, 1>& qq, const Eigen::Matrix<double, 1, 1>& uu) {
    return Eigen::Matrix<double, 1, 1>((-k * qq[0] - c * uu[0]) / m);
  };
  const auto step = rosenbrock_step(kRodas4, lin, 0.0, q, u, h, acceleration);
  const double omega = std::sqrt(k / m);
  EXPECT_LT(std::abs(step.q[0]), 1e-4 * std::abs(q[0]));
  EXPECT_LT(std::abs(step.u[0]) / omega, 1e-4 * std::abs(q[0]));
}

}  // namespace
}  // namespace rover
