// Makkar friction coefficient (paper eq. 8; docs/model.md §6, item 5).
//
//   mu(v) = g1 (tanh(g2 v) - tanh(g3 v)) + g4 tanh(g5 v) + g6 v
//
// v is the slip speed [m/s]; mu is dimensionless. The g1 term is the Stribeck
// hump (static peak falling to the kinetic level), g4 tanh(g5 v) the Coulomb
// level, g6 v viscous dissipation. mu is odd in v and mu(0) = 0, so the
// friction force -mu(|v_t|) F_n v_t/|v_t| is continuous at zero slip.
// Hot path: evaluated for every contact in every right-hand side; where both
// mu and mu' are wanted, makkar_mu_and_derivative() shares the three tanh.
#pragma once

#include <array>
#include <cmath>

namespace rover {

// [g1, g2, g3, g4, g5, g6]; g2, g3, g5 in s/m, g6 in s/m, g1 and g4 dimensionless.
using MakkarGammas = std::array<double, 6>;

// Friction coefficient at slip speed v [m/s].
inline double makkar_mu(double slip_speed_mps, const MakkarGammas& g) {
  const double v = slip_speed_mps;
  return g[0] * (std::tanh(g[1] * v) - std::tanh(g[2] * v)) + g[3] * std::tanh(g[4] * v) +
         g[5] * v;
}

// d mu / d v [s/m]; uses d tanh(x)/dx = 1 - tanh(x)^2.
inline double makkar_mu_derivative(double slip_speed_mps, const MakkarGammas& g) {
  const double v = slip_speed_mps;
  const auto sech2 = [](double x) {
    const double t = std::tanh(x);
    return 1.0 - t * t;
  };
  return g[0] * (g[1] * sech2(g[1] * v) - g[2] * sech2(g[2] * v)) + g[3] * g[4] * sech2(g[4] * v) +
         g[5];
}

struct MakkarMuAndDerivative {
  double mu = 0.0;        // makkar_mu()
  double d_mu_d_v = 0.0;  // makkar_mu_derivative() [s/m]
};

// Both at once, from one tanh per term (the same values as the two functions).
inline MakkarMuAndDerivative makkar_mu_and_derivative(double slip_speed_mps, const MakkarGammas& g) {
  const double v = slip_speed_mps;
  const double t2 = std::tanh(g[1] * v), t3 = std::tanh(g[2] * v), t5 = std::tanh(g[4] * v);
  return {g[0] * (t2 - t3) + g[3] * t5 + g[5] * v,
          g[0] * (g[1] * (1.0 - t2 * t2) - g[2] * (1.0 - t3 * t3)) + g[3] * g[4] * (1.0 - t5 * t5) + g[5]};
}

}  // namespace rover
