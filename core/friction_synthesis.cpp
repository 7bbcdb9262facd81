// Friction synthesis (docs/model.md §6, "Friction synthesis").
//
// Dimensionless form. With s = v / v_s and m = mu / mu_s the target is
// T(s) = mu_target(s v_s) / mu_s, which depends only on r_mu = mu_k / mu_s and
// r_v = v_k / v_s, and the Makkar model is
//   m(s) = a1 (tanh(b2 s) - tanh(b3 s)) + a4 tanh(b5 s) + a6 s,
//   a1 = g1 / mu_s, b2 = g2 v_s, b3 = g3 v_s, a4 = g4 / mu_s, b5 = g5 v_s, a6 = g6 v_s / mu_s.
//
// Variable projection (Golub & Pereyra). m is linear in the amplitudes
// (a1, a4, a6), so for given rates (b2, b3, b5) the best non-negative
// amplitudes solve a 3-variable non-negative least-squares problem exactly
// (every active set is tried). The optimisers then search only the three rates,
// on a log scale: a global NLopt search followed by a local polish. The
// projected problem has no ridge at a1 -> infinity (b2 -> b3) to get lost on,
// and its minima are minima of the full 6-parameter problem.
#include "core/friction_synthesis.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <boost/math/tools/minima.hpp>
#include <nlopt.hpp>

#include "core/number_text.hpp"

namespace rover {
namespace {

void check_engineering_parameters(const FrictionParameters& p) {
  const bool finite = std::isfinite(p.mu_static) && std::isfinite(p.mu_kinetic) &&
                      std::isfinite(p.v_static_mps) && std::isfinite(p.v_kinetic_mps);
  const bool frictionless = p.mu_static == 0.0 && p.mu_kinetic == 0.0;
  if (!finite || !(p.mu_static > 0.0 || frictionless) || !(p.mu_kinetic >= 0.0) ||
      !(p.v_static_mps > 0.0) || !(p.v_kinetic_mps > p.v_static_mps)) {
    throw std::invalid_argument(
        "friction: need mu_s > 0 (or mu_s = mu_k = 0), mu_k >= 0 and 0 < v_s < v_k; got mu_s = " +
        std::to_string(p.mu_static) + ", v_s = " + std::to_string(p.v_static_mps) +
        " m/s, mu_k = " + std::to_string(p.mu_kinetic) +
        ", v_k = " + std::to_string(p.v_kinetic_mps) + " m/s");
  }
}

// Upper end of the fit and quality range: 10 v_k.
double fit_range_mps(const FrictionParameters& p) { return 10.0 * p.v_kinetic_mps; }

// v_i = v_max i / (n - 1), i = 0..n-1.
double grid_point(double v_max, int i, int n) {
  return v_max * static_cast<double>(i) / static_cast<double>(n - 1);
}

// The dimensionless problem: the parameters with mu_s = v_s = 1.
FrictionParameters dimensionless(const FrictionParameters& p) {
  FrictionParameters d;
  d.mu_static = 1.0;
  d.v_static_mps = 1.0;
  d.mu_kinetic = p.mu_kinetic / p.mu_static;
  d.v_kinetic_mps = p.v_kinetic_mps / p.v_static_mps;
  return d;
}

// Rates searched: x = [ln b2, ln(b2 / b3), ln b5] (b2 >= b3 makes the g1 term
// the positive Stribeck hump).
struct Rates {
  double b2, b3, b5;
};
Rates rates_from(const std::vector<double>& x) {
  return {std::exp(x[0]), std::exp(x[0] - x[1]), std::exp(x[2])};
}

// Least squares of the dimensionless model against the sampled target, with
// the amplitudes projected out.
class ProjectedLeastSquares {
 public:
  using Vec = Eigen::Matrix<double, 3, 1>;

  ProjectedLeastSquares(const FrictionParameters& d, int samples)
      : s_max_(fit_range_mps(d)), s_(samples), target_(samples) {
    for (int i = 0; i < samples; ++i) {
      s_[i] = grid_point(s_max_, i, samples);
      target_[i] = friction_target_mu(s_[i], d);
    }
  }

  double s_max() const { return s_max_; }

  // Best amplitudes [a1, a4, a6 s_max] >= 0 for the rates; `mse` gets the mean
  // squared error.
  Vec amplitudes(const Rates& r, double* mse) const {
    // Normal equations of the columns phi = [hump, coulomb, s / s_max].
    Eigen::Matrix3d gram = Eigen::Matrix3d::Zero();
    Vec rhs = Vec::Zero();
    double tt = 0.0;
    for (std::size_t i = 0; i < s_.size(); ++i) {
      const double s = s_[i];
      const Vec phi(std::tanh(r.b2 * s) - std::tanh(r.b3 * s), std::tanh(r.b5 * s), s / s_max_);
      gram.selfadjointView<Eigen::Lower>().rankUpdate(phi);
      rhs += phi * target_[i];
      tt += target_[i] * target_[i];
    }
    gram.triangularView<Eigen::StrictlyUpper>() = gram.transpose();
    // Non-negative least squares by enumeration of the supports: the optimum
    // is the unconstrained solution on its support, and it is feasible.
    Vec best = Vec::Zero();
    double best_sse = tt;
    for (int support = 1; support < 8; ++support) {
      // Inactive amplitudes are pinned to zero by identity rows and columns.
      Eigen::Matrix3d g = gram;
      Vec b = rhs;
      for (int j = 0; j < 3; ++j) {
        if (support & (1 << j)) continue;
        g.row(j).setZero();
        g.col(j).setZero();
        g(j, j) = 1.0;
        b(j) = 0.0;
      }
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(g);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) continue;
      const Vec a = ldlt.solve(b);
      if (!a.allFinite() || (a.array() < 0.0).any()) continue;
      const double sse = tt - 2.0 * a.dot(rhs) + a.dot(gram * a);
      if (sse < best_sse) best_sse = sse, best = a;
    }
    if (mse) *mse = std::max(best_sse, 0.0) / static_cast<double>(s_.size());
    return best;
  }

  double mean_squared_error(const std::vector<double>& x) const {
    double mse = 0.0;
    amplitudes(rates_from(x), &mse);
    return mse;
  }

 private:
  double s_max_;
  std::vector<double> s_, target_;
};

double nlopt_objective(const std::vector<double>& x, std::vector<double>& /*grad*/, void* data) {
  return static_cast<const ProjectedLeastSquares*>(data)->mean_squared_error(x);
}

// Runs `opt` from x; a round-off stop still leaves the best point in x.
// Runs `opt` from x, clamped into its bounds first: a point on a bound can
// come back from a search a rounding error outside it, which NLopt refuses
// ("bounds fail").
void run(nlopt::opt& opt, std::vector<double>& x) {
  const std::vector<double> lower = opt.get_lower_bounds(), upper = opt.get_upper_bounds();
  for (std::size_t k = 0; k < x.size(); ++k) x[k] = std::clamp(x[k], lower[k], upper[k]);
  double f = 0.0;
  try {
    opt.optimize(x, f);
  } catch (const nlopt::roundoff_limited&) {
  }
}

}  // namespace

double friction_step(double x, double x0, double h0, double x1, double h1) {
  const double a = std::clamp((x - x0) / (x1 - x0), 0.0, 1.0);
  return h0 + (h1 - h0) * a * a * (3.0 - 2.0 * a);
}

double friction_target_mu(double v, const FrictionParameters& p) {
  if (v < 0.0) return -friction_target_mu(-v, p);
  const double mu_s = p.mu_static, v_s = p.v_static_mps;
  const double mu_k = p.mu_kinetic, v_k = p.v_kinetic_mps;
  if (v <= v_s) return friction_step(v, -v_s, -mu_s, v_s, mu_s);
  if (v <= v_k) return friction_step(v, v_s, mu_s, v_k, mu_k);
  return mu_k;
}

FrictionFitQuality friction_fit_quality(const MakkarGammas& gammas, const FrictionParameters& p) {
  check_engineering_parameters(p);
  const int n = kFrictionQualitySamples;
  const double v_max = fit_range_mps(p);
  double sum = 0.0;
  int best = 0;
  double best_mu = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    const double v = grid_point(v_max, i, n);
    const double mu = makkar_mu(v, gammas);
    const double r = mu - friction_target_mu(v, p);
    sum += r * r;
    if (mu > best_mu) best_mu = mu, best = i;
  }
  FrictionFitQuality q;
  q.rms = std::sqrt(sum / n);
  q.peak_mu = best_mu;
  q.peak_speed_mps = grid_point(v_max, best, n);
  if (!std::isfinite(q.rms)) {  // e.g. gammas not set (NaN)
    q.acceptable = false;
    return q;
  }
  // Refine the grid maximum within its neighbouring cells.
  const double lo = grid_point(v_max, std::max(best - 1, 0), n);
  const double hi = grid_point(v_max, std::min(best + 1, n - 1), n);
  std::uintmax_t max_iterations = 200;
  const auto [v_peak, minus_mu] = boost::math::tools::brent_find_minima(
      [&](double v) { return -makkar_mu(v, gammas); }, lo, hi,
      std::numeric_limits<double>::digits / 2, max_iterations);
  if (-minus_mu > q.peak_mu) {
    q.peak_mu = -minus_mu;
    q.peak_speed_mps = v_peak;
  }
  q.acceptable = q.rms < kFrictionMaxRms &&
                 std::abs(q.peak_mu - p.mu_static) <= kFrictionMaxPeakError * p.mu_static;
  return q;
}

MakkarGammas synthesize_friction(const FrictionParameters& p,
                                 const FrictionSynthesisOptions& options) {
  check_engineering_parameters(p);
  if (options.fit_samples < 2 || options.max_evaluations_global < 1 ||
      options.max_evaluations_local < 1)
    throw std::invalid_argument("synthesize_friction: need fit_samples >= 2 and positive budgets");

  if (p.mu_static == 0.0) return {};  // frictionless

  const FrictionParameters d = dimensionless(p);
  ProjectedLeastSquares problem(d, options.fit_samples);

  // Rates from a decay over ~10 v_k (the slowest useful) to a rise over
  // v_s / 100. b2 >= 1.01 b3 keeps g1 bounded: as b3 -> b2 the hump tends to
  // c s / cosh^2(b2 s) with a1 -> infinity, which the bound approximates
  // closely without the cancellation.
  const double ln_rate_min = std::log(0.1 / problem.s_max());
  const double ln_rate_max = std::log(100.0);
  const double ln_ratio_min = std::log(1.01);
  const std::vector<double> lower{ln_rate_min, ln_ratio_min, ln_rate_min};
  const std::vector<double> upper{ln_rate_max, ln_rate_max - ln_rate_min, ln_rate_max};
  std::vector<double> x(3);
  for (std::size_t k = 0; k < x.size(); ++k) x[k] = 0.5 * (lower[k] + upper[k]);

  // Global: multi-level single linkage on a Sobol sequence, each local search
  // a BOBYQA run; it spends the whole evaluation budget.
  nlopt::opt searches(nlopt::LN_BOBYQA, 3);
  searches.set_xtol_rel(1e-6);
  searches.set_maxeval(500);
  nlopt::opt global(nlopt::GN_MLSL_LDS, 3);
  global.set_local_optimizer(searches);
  global.set_lower_bounds(lower);
  global.set_upper_bounds(upper);
  global.set_min_objective(nlopt_objective, &problem);
  global.set_maxeval(options.max_evaluations_global);
  // NLopt's random generator is per thread; seeding it right before the run
  // makes the result a function of the input alone.
  nlopt::srand(options.seed);
  run(global, x);

  // Local polish of the best point to full precision.
  nlopt::opt local(nlopt::LN_BOBYQA, 3);
  local.set_lower_bounds(lower);
  local.set_upper_bounds(upper);
  local.set_min_objective(nlopt_objective, &problem);
  local.set_maxeval(options.max_evaluations_local);
  local.set_xtol_rel(1e-10);
  run(local, x);

  const Rates r = rates_from(x);
  const ProjectedLeastSquares::Vec a = problem.amplitudes(r, nullptr);
  const double mu_s = p.mu_static, v_s = p.v_static_mps;
  const MakkarGammas gammas{mu_s * a(0), r.b2 / v_s, r.b3 / v_s,
                            mu_s * a(1), r.b5 / v_s, mu_s * a(2) / (problem.s_max() * v_s)};
  for (const double g : gammas)
    if (!std::isfinite(g))
      throw std::invalid_argument("the gammas of this law overflow a double (gamma = " + number_text(g) +
                                  " from the dimensionless fit scaled by mu_s = " + number_text(mu_s) +
                                  ", v_s = " + number_text(v_s) + " m/s)");
  return gammas;
}

MakkarGammas friction_gammas_for(const FrictionParameters& p) {
  // Pinned gammas only for the engineering parameters they were fitted to: a
  // small change of mu_s (still inside the quality bar) must change the model.
  const std::array<double, 4> engineering{p.mu_static, p.v_static_mps, p.mu_kinetic, p.v_kinetic_mps};
  if (engineering == p.gammas_fitted_to && friction_fit_quality(p.gammas, p).acceptable)
    return p.gammas;
  return synthesize_friction(p);
}

FrictionParameters with_friction_speeds_scaled(FrictionParameters p, double scale) {
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw std::invalid_argument("friction speed scale must be positive and finite, got " +
                                number_text(scale));
  p.v_static_mps *= scale;
  p.v_kinetic_mps *= scale;
  for (const int g : {1, 2, 4, 5}) p.gammas[static_cast<std::size_t>(g)] /= scale;
  p.gammas_fitted_to = {p.mu_static, p.v_static_mps, p.mu_kinetic, p.v_kinetic_mps};
  return p;
}

}  // namespace rover
