// Makkar friction coefficient (paper eq. 8; docs/model.md §6, item 5).
//
//   mu(v) = g1 (tanh(g2 v) - tanh(g3 v)) + g4 tanh(g5 v) + g6 v
//
// v is the slip speed [m/s]; mu is dimensionless. The g1 term is the Stribeck
// hump (static peak falling to the kinetic level), g4 tanh(g5 v) the Coulomb
// level, g6 v viscous dissipation. mu is odd in v and mu(0) = 0, so the
// friction force -mu(|v_t|) F_n v_t/|v_t| is continuous at zero slip.
// Hot path: evaluated for every contact in every right-hand side; where both
// mu and mu' are wanted, makkar_mu_and_derivative() shares the three tanh
// (makkar_tanh()).
#pragma once

#include <array>
#include <cmath>

namespace rover {

// [g1, g2, g3, g4, g5, g6]; g2, g3, g5 in s/m, g6 in s/m, g1 and g4 dimensionless.
using MakkarGammas = std::array<double, 6>;

// Friction coefficient at slip speed v [m/s].
// The three transcendental terms of mu and mu' at one slip speed v:
// tanh(g2 v), tanh(g3 v) and tanh(g5 v). A contact's force evaluation keeps
// them (ContactPoint::friction_tanh), so that the Jacobian and the step
// control at the same state take mu and mu' from them without new tanh.
struct MakkarTanh {
  double t2 = 0.0, t3 = 0.0, t5 = 0.0;
};

inline MakkarTanh makkar_tanh(double slip_speed_mps, const MakkarGammas& g) {
  const double v = slip_speed_mps;
  return {std::tanh(g[1] * v), std::tanh(g[2] * v), std::tanh(g[4] * v)};
}

// mu(v) from makkar_tanh(v, g).
inline double makkar_mu(double slip_speed_mps, const MakkarGammas& g, const MakkarTanh& t) {
  return g[0] * (t.t2 - t.t3) + g[3] * t.t5 + g[5] * slip_speed_mps;
}

inline double makkar_mu(double slip_speed_mps, const MakkarGammas& g) {
  return makkar_mu(slip_speed_mps, g, makkar_tanh(slip_speed_mps, g));
}

// mu'(v) from makkar_tanh(v, g).
inline double makkar_mu_derivative(const MakkarGammas& g, const MakkarTanh& t) {
  return g[0] * (g[1] * (1.0 - t.t2 * t.t2) - g[2] * (1.0 - t.t3 * t.t3)) + g[3] * g[4] * (1.0 - t.t5 * t.t5) +
         g[5];
}

inline double makkar_mu_derivative(double slip_speed_mps, const MakkarGammas& g) {
  return makkar_mu_derivative(g, makkar_tanh(slip_speed_mps, g));
}

struct MakkarMuAndDerivative {
  double mu = 0.0;        // makkar_mu()
  double d_mu_d_v = 0.0;  // makkar_mu_derivative() [s/m]
};

inline MakkarMuAndDerivative makkar_mu_and_derivative(double slip_speed_mps, const MakkarGammas& g,
                                                      const MakkarTanh& t) {
  return {makkar_mu(slip_speed_mps, g, t), makkar_mu_derivative(g, t)};
}

inline MakkarMuAndDerivative makkar_mu_and_derivative(double slip_speed_mps, const MakkarGammas& g) {
  return makkar_mu_and_derivative(slip_speed_mps, g, makkar_tanh(slip_speed_mps, g));
}

}  // namespace rover
