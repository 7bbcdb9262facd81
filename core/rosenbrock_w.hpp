// One step of the Rosenbrock-W method ROS34PW2 (J. Rang and L. Angermann, BIT
// 45 (2005) 761-787) for a mechanical system in second-order form
//   dq/dt = u,   M(q) du/dt = F(t, q, u),
// with the stiff forces treated linearly implicitly (docs/model.md §9).
//
// ROS34PW2 has four stages, order 3 with an embedded order-2 solution for the
// step-size control, and is L-stable (R(inf) = 0; the embedded method is
// A-stable with R(inf) = 0.48). It is a W-method: it keeps its order with ANY
// matrix in place of the Jacobian of the right-hand side, so an approximate
// Jacobian that captures the stiff forces (force_jacobian.hpp) is enough.
//
// Written in the transformed variables U_i = sum_j gamma_ij k_j (Hairer and
// Wanner, Solving ODEs II, IV.7, eq. 7.4'), each stage solves
//   (I / (h g) - J) U_i = f(x + sum_j a_ij U_j) + sum_j (c_ij / h) U_j
// with the approximate Jacobian of x = [q; u]
//   J = [0, I; M0^{-1} K, M0^{-1} D],  D ~ dF/du, K ~ dF/dq at the step start,
// which reduces (multiply the u rows by h g M0 and eliminate U_q) to one N x N
// system per stage with a single matrix per step:
//   (M0 - h g D - h^2 g^2 K) U_u = h g (M0 r_u + h g K r_q),  U_q = h g (r_q + U_u),
// where r = [r_q; r_u] is the right-hand side above. A time dependence of F is
// taken at the stage times t + alpha_i h and left out of J (a W-method allows it).
//
// The same machinery runs RODAS4 (Hairer and Wanner, Solving ODEs II, IV.7,
// Table 7.2; the coefficients of their code rodas.f, METH = 1): six stages,
// order 4 with an embedded order-3 solution, L-stable and stiffly accurate
// (the last two stages sit at t0 + h and the solution is the last stage
// point). It is a classical Rosenbrock method, not a W-method: its order 4
// needs the exact Jacobian of dx/dt and an autonomous system; with the
// approximate J above (the stiff forces only, no dM/dq, no df/dt) its
// order falls to the terms that J leaves out, which on the rover are small
// next to the stiff ones (force_jacobian.hpp); rosenbrock_w_test.cpp shows both.
#pragma once

#include <array>
#include <cmath>
#include <utility>

#include <Eigen/Core>
#include <Eigen/LU>

#include "core/fixed_size_product.hpp"

namespace rover {

// The system linearized at the start (t0, q0, u0) of a step.
template <int N>
struct MechanicalLinearization {
  using Vector = Eigen::Matrix<double, N, 1>;
  using Matrix = Eigen::Matrix<double, N, N>;
  Matrix mass = Matrix::Zero();                // M(q0)
  Vector force = Vector::Zero();               // F(t0, q0, u0)
  Matrix d_force_d_speed = Matrix::Zero();     // D, at least its stiff part
  Matrix d_force_d_position = Matrix::Zero();  // K, at least its stiff part
};

template <int N>
struct RosenbrockWStep {
  using Vector = Eigen::Matrix<double, N, 1>;
  Vector q, u;              // third-order solution at t0 + h
  Vector error_q, error_u;  // third- minus embedded second-order solution
};

// Coefficients of a Rosenbrock(-W) method in the transformed form (a, c, m,
// m_hat of Hairer and Wanner, IV.7, eq. 7.4'), with `Stages` stages.
template <int Stages>
struct RosenbrockTableau {
  static constexpr int kStages = Stages;
  double gamma = 0.0;                                  // diagonal gamma_ii
  std::array<std::array<double, Stages>, Stages> a{};  // strictly lower
  std::array<std::array<double, Stages>, Stages> c{};  // strictly lower
  std::array<double, Stages> m{}, m_error{};           // m and m - m_hat
  std::array<double, Stages> stage_time{};             // alpha_i = sum_j alpha_ij
  int embedded_order = 0;                              // local error of the estimate ~ h^(embedded_order + 1)
};
using RosenbrockWTableau = RosenbrockTableau<4>;  // ROS34PW2

namespace detail {

constexpr RosenbrockWTableau make_ros34pw2_tableau() {
  constexpr int s = RosenbrockWTableau::kStages;
  // Rang and Angermann (2005), ROS34PW2: alpha_ij, gamma_ij, b_i, b_hat_i.
  const double g = 4.3586652150845900e-01;
  const double alpha[s][s] = {{0.0, 0.0, 0.0, 0.0},
                              {8.7173304301691801e-01, 0.0, 0.0, 0.0},
                              {8.4457060015369423e-01, -1.1299064236484185e-01, 0.0, 0.0},
                              {0.0, 0.0, 1.0, 0.0}};
  const double gamma[s][s] = {{g, 0.0, 0.0, 0.0},
                              {-8.7173304301691801e-01, g, 0.0, 0.0},
                              {-9.0338057013044082e-01, 5.4180672388095326e-02, g, 0.0},
                              {2.4212380706095346e-01, -1.2232505839045147e+00,
                               5.4526025533510214e-01, g}};
  const double b[s] = {2.4212380706095346e-01, -1.2232505839045147e+00, 1.5452602553351020e+00,
                       4.3586652150845900e-01};
  const double b_hat[s] = {3.7810903145819369e-01, -9.6042292212423178e-02, 0.5,
                           2.1793326075422950e-01};
  // Inverse of the lower-triangular Gamma by forward substitution.
  double inv[s][s] = {};
  for (int j = 0; j < s; ++j) {
    inv[j][j] = 1.0 / gamma[j][j];
    for (int i = j + 1; i < s; ++i) {
      double sum = 0.0;
      for (int k = j; k < i; ++k) sum += gamma[i][k] * inv[k][j];
      inv[i][j] = -sum / gamma[i][i];
    }
  }
  RosenbrockWTableau t;
  t.gamma = g;
  t.embedded_order = 2;
  for (int i = 0; i < s; ++i) {
    for (int j = 0; j < i; ++j) {
      double sum = 0.0;
      for (int k = j; k < i; ++k) sum += alpha[i][k] * inv[k][j];
      t.a[i][j] = sum;
      t.c[i][j] = -inv[i][j];
      t.stage_time[i] += alpha[i][j];
    }
    double m = 0.0, m_hat = 0.0;
    for (int k = i; k < s; ++k) {
      m += b[k] * inv[k][i];
      m_hat += b_hat[k] * inv[k][i];
    }
    t.m[i] = m;
    t.m_error[i] = m - m_hat;
  }
  return t;
}

// RODAS4 as printed in rodas.f (Hairer and Wanner), already in the
// transformed form: stage 6 is stage 5's point plus U_5, the solution stage
// 6's point plus U_6, and the embedded solution stage 6's point (m - m_hat
// = e_6).
constexpr RosenbrockTableau<6> make_rodas4_tableau() {
  RosenbrockTableau<6> t;
  t.gamma = 0.25;
  t.embedded_order = 3;
  t.stage_time = {0.0, 0.386, 0.21, 0.63, 1.0, 1.0};
  t.a[1] = {1.544, 0.0, 0.0, 0.0, 0.0, 0.0};
  t.a[2] = {0.9466785280815826, 0.2557011698983284, 0.0, 0.0, 0.0, 0.0};
  t.a[3] = {3.314825187068521, 2.896124015972201, 0.9986419139977817, 0.0, 0.0, 0.0};
  t.a[4] = {1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950, 0.0, 0.0};
  t.a[5] = {1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950, 1.0, 0.0};
  t.c[1] = {-5.6688, 0.0, 0.0, 0.0, 0.0, 0.0};
  t.c[2] = {-2.430093356833875, -0.2063599157091915, 0.0, 0.0, 0.0, 0.0};
  t.c[3] = {-0.1073529058151375, -9.594562251023355, -20.47028614809616, 0.0, 0.0, 0.0};
  t.c[4] = {7.496443313967647, -10.24680431464352, -33.99990352819905, 11.70890893206160, 0.0, 0.0};
  t.c[5] = {8.083246795921522, -7.981132988064893, -31.52159432874371, 16.31930543123136,
            -6.058818238834054, 0.0};
  t.m = {1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950, 1.0, 1.0};
  t.m_error = {0.0, 0.0, 0.0, 0.0, 0.0, 1.0};
  return t;
}

}  // namespace detail

inline constexpr RosenbrockWTableau kRos34pw2 = detail::make_ros34pw2_tableau();
inline constexpr RosenbrockTableau<6> kRodas4 = detail::make_rodas4_tableau();

// The iteration matrix M0 - h g D - h^2 g^2 K of a step of size h for a
// method with diagonal gamma g (the top of the file); a factorization of it
// is the one linear solver of the step.
template <int N>
Eigen::Matrix<double, N, N> rosenbrock_iteration_matrix(const MechanicalLinearization<N>& lin, double h,
                                                        double gamma) {
  const double hg = h * gamma;
  return lin.mass - hg * lin.d_force_d_speed - (hg * hg) * lin.d_force_d_position;
}

template <int N>
Eigen::Matrix<double, N, N> ros34pw2_iteration_matrix(const MechanicalLinearization<N>& lin, double h) {
  const double hg = h * kRos34pw2.gamma;
  return lin.mass - hg * lin.d_force_d_speed - (hg * hg) * lin.d_force_d_position;
}

// One step of the method `tab` of size h from (t0, q0, u0), linearized there
// as `lin`, with `iteration` a factorization (anything with Vector
// solve(Vector)) of rosenbrock_iteration_matrix(lin, h, tab.gamma).
// acceleration(t, q, u) must return M(q)^{-1} F(t, q, u); it is called once
// per stage after the first (which uses lin.force). Non-finite results (a
// singular iteration matrix, a blown-up stage) propagate into q, u and the
// error, for the caller's step control to reject.
template <int N, int Stages, class Factorization, class Acceleration>
RosenbrockWStep<N> rosenbrock_step(const RosenbrockTableau<Stages>& tab, const MechanicalLinearization<N>& lin,
                                   const Factorization& iteration, double t0,
                                   const Eigen::Matrix<double, N, 1>& q0,
                                   const Eigen::Matrix<double, N, 1>& u0, double h,
                                   Acceleration&& acceleration) {
  using Vector = Eigen::Matrix<double, N, 1>;
  const double hg = h * tab.gamma;

  std::array<Vector, Stages> Uq, Uu;  // transformed stage increments
  RosenbrockWStep<N> out{q0, u0, Vector::Zero(), Vector::Zero()};
  for (int i = 0; i < Stages; ++i) {
    // Stage point x + sum_j a_ij U_j and the right-hand side r of the stage.
    Vector q = q0, u = u0, rq, ru_correction = Vector::Zero();
    for (int j = 0; j < i; ++j) {
      add_scaled(q, tab.a[i][j], Uq[j]);
      add_scaled(u, tab.a[i][j], Uu[j]);
    }
    rq = u;
    for (int j = 0; j < i; ++j) {
      add_scaled(rq, tab.c[i][j] / h, Uq[j]);
      add_scaled(ru_correction, tab.c[i][j] / h, Uu[j]);
    }
    // M0 r_u, where for the first stage M0 f_u(x) = M0 M0^{-1} F0 = F0.
    const Vector mass_ru =
        i == 0 ? lin.force
               : fixed_size_product(lin.mass, Vector(acceleration(t0 + tab.stage_time[i] * h, q, u) + ru_correction),
                                    1.0);
    const Vector stiffness_rq = fixed_size_product(lin.d_force_d_position, rq, hg);  // hg K r_q
    Uu[i] = iteration.solve(Vector(hg * (mass_ru + stiffness_rq)));
    Uq[i] = hg * (rq + Uu[i]);
    add_scaled(out.q, tab.m[i], Uq[i]);
    add_scaled(out.u, tab.m[i], Uu[i]);
    add_scaled(out.error_q, tab.m_error[i], Uq[i]);
    add_scaled(out.error_u, tab.m_error[i], Uu[i]);
  }
  return out;
}

// One ROS34PW2 step of size h from (t0, q0, u0), linearized there as `lin`,
// with `iteration` a factorization (anything with Vector solve(Vector)) of
// ros34pw2_iteration_matrix(lin, h). acceleration(t, q, u) must return
// M(q)^{-1} F(t, q, u); it is called three times (the first stage uses
// lin.force). Non-finite results (a singular iteration matrix, a blown-up
// stage) propagate into q, u and the error, for the caller's step control to
// reject.
template <int N, class Factorization, class Acceleration>
RosenbrockWStep<N> ros34pw2_step(const MechanicalLinearization<N>& lin, const Factorization& iteration,
                                 double t0, const Eigen::Matrix<double, N, 1>& q0,
                                 const Eigen::Matrix<double, N, 1>& u0, double h,
                                 Acceleration&& acceleration) {
  return rosenbrock_step(kRos34pw2, lin, iteration, t0, q0, u0, h, std::forward<Acceleration>(acceleration));
}

// The same steps with a dense LU of the iteration matrix.
template <int N, int Stages, class Acceleration>
RosenbrockWStep<N> rosenbrock_step(const RosenbrockTableau<Stages>& tab, const MechanicalLinearization<N>& lin,
                                   double t0, const Eigen::Matrix<double, N, 1>& q0,
                                   const Eigen::Matrix<double, N, 1>& u0, double h,
                                   Acceleration&& acceleration) {
  const Eigen::PartialPivLU<Eigen::Matrix<double, N, N>> iteration(rosenbrock_iteration_matrix(lin, h, tab.gamma));
  return rosenbrock_step(tab, lin, iteration, t0, q0, u0, h, std::forward<Acceleration>(acceleration));
}

template <int N, class Acceleration>
RosenbrockWStep<N> ros34pw2_step(const MechanicalLinearization<N>& lin, double t0,
                                 const Eigen::Matrix<double, N, 1>& q0,
                                 const Eigen::Matrix<double, N, 1>& u0, double h,
                                 Acceleration&& acceleration) {
  const Eigen::PartialPivLU<Eigen::Matrix<double, N, N>> iteration(ros34pw2_iteration_matrix(lin, h));
  return ros34pw2_step<N>(lin, iteration, t0, q0, u0, h, std::forward<Acceleration>(acceleration));
}

}  // namespace rover
