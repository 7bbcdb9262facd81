// Friction synthesis: Makkar gammas from the engineering parameters
// (docs/model.md §6, "Friction synthesis"; paper section 2.2.3 after eq. 8).
//
// The engineering parameters mu_s, v_s, mu_k, v_k define a STEP-based target
// curve mu_target(v); the six gammas of eq. 8 are fitted to it by least squares
// on v in [0, 10 v_k] with all gammas >= 0 (global search, then local polish).
// A fit is acceptable when its RMS error is below 0.01 and its peak lies
// within 5 % of mu_s.
#pragma once

#include "core/friction.hpp"
#include "core/rover_parameters.hpp"

namespace rover {

// The cubic step of docs/model.md: h0 + (h1 - h0) a^2 (3 - 2 a),
// a = clamp((x - x0) / (x1 - x0), 0, 1). Requires x1 > x0.
double friction_step(double x, double x0, double h0, double x1, double h1);

// Target friction coefficient at slip speed v [m/s] (docs/model.md, piecewise):
//   STEP(v, -v_s, -mu_s, v_s, mu_s)  for 0 <= v <= v_s
//   STEP(v,  v_s,  mu_s, v_k, mu_k)  for v_s < v <= v_k
//   mu_k                             for v > v_k
// and extended as an odd function to v < 0 (like mu itself).
// Only the engineering parameters of `p` are used, not p.gammas.
double friction_target_mu(double v, const FrictionParameters& p);

struct FrictionFitQuality {
  double rms = 0.0;             // RMS of mu - mu_target over the quality grid
  double peak_mu = 0.0;         // maximum of mu(v) on v in [0, 10 v_k]
  double peak_speed_mps = 0.0;  // where the maximum is
  bool acceptable = false;      // rms < 0.01 and |peak_mu - mu_s| <= 0.05 mu_s
};

// Number of points of the quality grid: v_i = 10 v_k i / (n - 1), i = 0..n-1.
inline constexpr int kFrictionQualitySamples = 2001;
inline constexpr double kFrictionMaxRms = 0.01;
inline constexpr double kFrictionMaxPeakError = 0.05;  // relative to mu_s

// Quality of `gammas` for the engineering parameters of `p`: RMS on the fixed
// quality grid; peak by a grid search refined with Brent's method. Non-finite
// gammas give a non-finite rms and acceptable = false. Throws
// std::invalid_argument on bad engineering parameters (as synthesize_friction).
FrictionFitQuality friction_fit_quality(const MakkarGammas& gammas, const FrictionParameters& p);

struct FrictionSynthesisOptions {
  int fit_samples = 600;               // least-squares grid on [0, 10 v_k]
  int max_evaluations_global = 2000;   // NLopt GN_MLSL_LDS with LN_BOBYQA searches
  int max_evaluations_local = 2000;    // final NLopt LN_BOBYQA polish
  unsigned seed = 1;                   // NLopt random seed (determinism)
};

// Fits the gammas to the target curve of `p` (p.gammas are ignored). The fit
// runs in dimensionless variables (mu / mu_s, v / v_s), so it depends only on
// mu_k / mu_s and v_k / v_s: scaling mu_s and mu_k scales g1, g4, g6, scaling
// v_s and v_k scales g2, g3, g5, g6 inversely. Deterministic for a given input
// and seed. Returns the best fit found, which can miss the quality bar for
// extreme parameters (check friction_fit_quality). mu_s = mu_k = 0 gives all
// gammas 0. Throws std::invalid_argument unless mu_s > 0 (or mu_s = mu_k = 0),
// mu_k >= 0 and 0 < v_s < v_k (all finite).
MakkarGammas synthesize_friction(const FrictionParameters& p,
                                 const FrictionSynthesisOptions& options = {});

// The gammas to simulate with: p.gammas when they pass the quality bar for p's
// engineering parameters (so the default config keeps its pinned reference
// set), otherwise (also when they are NaN, i.e. not configured) a fresh
// synthesize_friction(p) with the default options.
MakkarGammas friction_gammas_for(const FrictionParameters& p);

// The same friction law on a speed axis `scale` times shorter: v_s and v_k
// times `scale`, g2, g3, g5 and g6 divided by it, so that the new mu(v) is the
// old mu(v / scale) and the gammas stay fitted to the new engineering
// parameters (the fit is dimensionless, see synthesize_friction). mu'(0), and
// with it the stiffness of stuck friction, grows by 1 / scale: the friction
// friction sharpness. Throws std::invalid_argument unless 0 < scale < inf.
FrictionParameters with_friction_speeds_scaled(FrictionParameters p, double scale);

}  // namespace rover
