// See gaussian_process.hpp.
#include "study/surrogate/gaussian_process.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <Eigen/Cholesky>
#include <nlopt.hpp>

#include "study/estimators/splitmix64.hpp"
#include "study/surrogate/matern_kernel.hpp"
#include "study/surrogate/output_magnitude.hpp"

namespace rover::study {
namespace {

constexpr double kMaxNugget = 0.1;
constexpr double kMaxEstimatedNugget = 10.0;
constexpr int kMaxStarts = 100;
constexpr int kMinEvaluations = 10;
// The objective returned where the correlation matrix is not positive definite.
constexpr double kFailedObjective = 1e300;
// The first start: every length-scale this fraction of the (unit) input range.
constexpr double kFirstStartLengthScale = 0.3;
// BOBYQA's first step and stopping tolerance, in log length-scale.
constexpr double kInitialLogStep = 0.5;
constexpr double kLogLengthTolerance = 1e-5;
// A sample variance at or below this fraction of the squared mean is zero.
constexpr double kConstantOutputRelativeVariance = 1e-28;
constexpr std::uint64_t kStartStream = 0x6A09E667F3BCC909ull;
constexpr std::uint64_t kNuggetStartStream = 0xBB67AE8584CAA73Bull;

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void check_settings(const GaussianProcessSettings& s) {
  const auto fail = [](const std::string& what) {
    throw std::invalid_argument("Gaussian process settings: " + what);
  };
  if (!(s.nugget >= 0.0 && s.nugget <= kMaxNugget))
    fail("nugget " + number(s.nugget) + " is outside [0, " + number(kMaxNugget) + "]");
  if (s.estimate_nugget && !(s.min_nugget > 0.0 && s.max_nugget > s.min_nugget && s.max_nugget <= kMaxEstimatedNugget))
    fail("nugget bounds [" + number(s.min_nugget) + ", " + number(s.max_nugget) + "] must satisfy 0 < min < max <= " +
         number(kMaxEstimatedNugget));
  if (s.starts < 1 || s.starts > kMaxStarts)
    fail("starts " + std::to_string(s.starts) + " is outside [1, " + std::to_string(kMaxStarts) + "]");
  if (s.max_evaluations < kMinEvaluations)
    fail("max_evaluations " + std::to_string(s.max_evaluations) + " is below " +
         std::to_string(kMinEvaluations));
  if (!(s.min_length_scale > 0.0 && s.max_length_scale > s.min_length_scale &&
        std::isfinite(s.max_length_scale)))
    fail("length-scale bounds [" + number(s.min_length_scale) + ", " + number(s.max_length_scale) +
         "] must satisfy 0 < min < max < inf");
  if (!(s.q2_threshold <= 1.0)) fail("q2_threshold " + number(s.q2_threshold) + " must be <= 1");
}

int trend_terms(KrigingTrend trend, Eigen::Index dims) {
  return trend == KrigingTrend::kConstant ? 1 : static_cast<int>(dims) + 1;
}

void check_data(const DesignMatrix& x, const Eigen::VectorXd& y, const GaussianProcessSettings& s,
                const std::string& name) {
  if (x.cols() < 1 || x.rows() != y.size())
    throw std::invalid_argument("Gaussian process: design is " + std::to_string(x.rows()) + " x " +
                                std::to_string(x.cols()) + " for " + std::to_string(y.size()) +
                                " output values; expected runs x inputs, one value per run");
  if (s.fixed_length_scales.size() > 0 &&
      (s.fixed_length_scales.size() != x.cols() || !(s.fixed_length_scales.array() > 0.0).all() ||
       !s.fixed_length_scales.allFinite()))
    throw std::invalid_argument("Gaussian process settings: fixed_length_scales has " +
                                std::to_string(s.fixed_length_scales.size()) +
                                " entries; it needs one finite value > 0 per input (" +
                                std::to_string(x.cols()) + ")");
  const int needed = trend_terms(s.trend, x.cols()) + 2;
  if (y.size() < needed)
    throw std::invalid_argument("Gaussian process: " + std::to_string(y.size()) + " runs for '" +
                                name + "'; the trend needs at least " + std::to_string(needed));
  for (Eigen::Index r = 0; r < y.size(); ++r)
    if (!std::isfinite(y(r)) || !x.row(r).allFinite())
      throw std::invalid_argument("Gaussian process: output '" + name + "' or its inputs are not "
                                  "finite at run " + std::to_string(r) +
                                  "; drop failed runs before fitting");
  if (const std::string problem = output_magnitude_problem(y, name); !problem.empty())
    throw std::invalid_argument("Gaussian process: " + problem);
  const double variance = (y.array() - y.mean()).square().mean();
  if (!(variance > kConstantOutputRelativeVariance * y.squaredNorm() / static_cast<double>(y.size())))
    throw std::invalid_argument("Gaussian process: output '" + name + "' is constant over its " +
                                std::to_string(y.size()) + " runs; there is nothing to fit");
}

Eigen::MatrixXd trend_matrix(const DesignMatrix& u, KrigingTrend trend) {
  Eigen::MatrixXd f(u.rows(), trend_terms(trend, u.cols()));
  f.col(0).setOnes();
  if (trend == KrigingTrend::kLinear) f.rightCols(u.cols()) = u;
  return f;
}

// Everything that depends on the length-scales, with beta and sigma^2 profiled out.
struct Profile {
  bool ok = false;
  Eigen::LLT<Eigen::MatrixXd> llt;  // of R
  Eigen::MatrixXd ft;               // L^-1 F
  Eigen::LLT<Eigen::MatrixXd> trend_llt;  // of F^T R^-1 F
  Eigen::VectorXd beta, residual;   // residual: L^-1 (y - F beta)
  double sigma2 = 0.0, objective = kFailedObjective;
};

Profile profile(const DesignMatrix& u, const Eigen::VectorXd& y, const Eigen::MatrixXd& f,
                const Eigen::VectorXd& length_scales, double nugget) {
  Profile p;
  Eigen::MatrixXd r = matern52_correlation(u, u, length_scales);
  r.diagonal().array() += nugget;
  p.llt.compute(r);
  if (p.llt.info() != Eigen::Success) return p;
  p.ft = p.llt.matrixL().solve(f);
  const Eigen::VectorXd yt = p.llt.matrixL().solve(y);
  p.trend_llt.compute(p.ft.transpose() * p.ft);
  if (p.trend_llt.info() != Eigen::Success) return p;
  p.beta = p.trend_llt.solve(p.ft.transpose() * yt);
  p.residual = yt - p.ft * p.beta;
  const double n = static_cast<double>(y.size());
  p.sigma2 = p.residual.squaredNorm() / n;
  const Eigen::MatrixXd l = p.llt.matrixL();
  const double log_det = 2.0 * l.diagonal().array().log().sum();
  if (!(p.sigma2 > 0.0) || !std::isfinite(log_det)) return p;
  p.objective = n * std::log(p.sigma2) + log_det;
  p.ok = std::isfinite(p.objective);
  return p;
}

// theta: the log length-scales and, when estimate_nugget, log tau last.
struct Problem {
  const DesignMatrix* u;
  const Eigen::VectorXd* y;
  const Eigen::MatrixXd* f;
  double nugget;  // when it is not estimated
  bool estimate_nugget;
  const std::atomic<bool>* stop;  // GaussianProcessSettings::stop
  bool stopped() const { return stop != nullptr && stop->load(); }
};

// d f / d log l_k = tr((R^-1 - w w^T / sigma^2) dR/dlog l_k), w = R^-1 (y - F beta)
// (beta and sigma^2 at their optimum, so their own derivatives drop out), with
// dR_ij/dlog l_k = 5/3 (1 + sqrt5 r) exp(-sqrt5 r) (d_ijk / l_k)^2, and
// dR/dlog tau = tau I, so d f / d log tau = tau tr(R^-1 - w w^T / sigma^2).
Eigen::MatrixXd gradient_kernel(const Profile& p, Eigen::Index n) {
  const Eigen::MatrixXd r_inv = p.llt.solve(Eigen::MatrixXd::Identity(n, n));
  const Eigen::VectorXd w = p.llt.matrixU().solve(p.residual);
  return r_inv - w * w.transpose() / p.sigma2;
}

Eigen::VectorXd objective_gradient(const Eigen::MatrixXd& a, const DesignMatrix& u,
                                   const Eigen::VectorXd& length_scales) {
  const Eigen::Index n = u.rows(), d = u.cols();
  const double sqrt5 = std::sqrt(5.0);
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(d);
  const DesignMatrix scaled = u.array().rowwise() / length_scales.transpose().array();
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j) {
      const Eigen::RowVectorXd diff = scaled.row(i) - scaled.row(j);
      const double r = diff.norm();
      const double factor = 2.0 * a(i, j) * (5.0 / 3.0) * (1.0 + sqrt5 * r) * std::exp(-sqrt5 * r);
      gradient += factor * diff.array().square().matrix().transpose();
    }
  return gradient;
}

double objective(const std::vector<double>& theta, std::vector<double>& gradient, void* data) {
  const Problem& pr = *static_cast<const Problem*>(data);
  if (pr.stopped()) throw nlopt::forced_stop();
  const Eigen::Index d = pr.u->cols();
  Eigen::VectorXd ls(d);
  for (Eigen::Index i = 0; i < d; ++i) ls(i) = std::exp(theta[static_cast<std::size_t>(i)]);
  const double nugget = pr.estimate_nugget ? std::exp(theta.back()) : pr.nugget;
  const Profile p = profile(*pr.u, *pr.y, *pr.f, ls, nugget);
  if (!gradient.empty()) {
    std::fill(gradient.begin(), gradient.end(), 0.0);
    if (p.ok) {
      const Eigen::MatrixXd a = gradient_kernel(p, pr.u->rows());
      const Eigen::VectorXd g = objective_gradient(a, *pr.u, ls);
      for (Eigen::Index i = 0; i < d; ++i) gradient[static_cast<std::size_t>(i)] = g(i);
      if (pr.estimate_nugget) gradient.back() = nugget * a.trace();
    }
  }
  return p.objective;
}

// The bounds of theta: log length-scales, then log tau when it is estimated.
struct ThetaBounds {
  std::vector<double> lower, upper;
};

ThetaBounds theta_bounds(int dims, const GaussianProcessSettings& s) {
  ThetaBounds b{std::vector<double>(static_cast<std::size_t>(dims), std::log(s.min_length_scale)),
                std::vector<double>(static_cast<std::size_t>(dims), std::log(s.max_length_scale))};
  if (s.estimate_nugget) {
    b.lower.push_back(std::log(s.min_nugget));
    b.upper.push_back(std::log(s.max_nugget));
  }
  return b;
}

std::vector<double> start_point(int start, int dims, const GaussianProcessSettings& s) {
  const double lo = std::log(s.min_length_scale), hi = std::log(s.max_length_scale);
  std::vector<double> theta(static_cast<std::size_t>(dims));
  // A number in [0, 1) from (seed, stream, index).
  const auto unit = [&](std::uint64_t stream, int index) {
    const std::uint64_t h = splitmix64(s.seed ^ splitmix64(stream + static_cast<std::uint64_t>(index)));
    return static_cast<double>(h >> 11) / 9007199254740992.0;
  };
  for (int i = 0; i < dims; ++i) {
    const double t = start > 0 ? lo + unit(kStartStream, start * dims + i) * (hi - lo) : std::log(kFirstStartLengthScale);
    theta[static_cast<std::size_t>(i)] = std::clamp(t, lo, hi);
  }
  // The nugget: the given one first, then anywhere in its range (the
  // likelihood often has a noise-free and a noisy optimum).
  if (s.estimate_nugget) {
    const double nlo = std::log(s.min_nugget), nhi = std::log(s.max_nugget);
    theta.push_back(start > 0 ? nlo + unit(kNuggetStartStream, start) * (nhi - nlo)
                              : std::log(std::clamp(s.nugget, s.min_nugget, s.max_nugget)));
  }
  return theta;
}

// The best theta (log length-scales, then log tau when estimated) over the starts.
std::vector<double> maximise_likelihood(const Problem& pr, int dims, const GaussianProcessSettings& s) {
  std::vector<double> best;
  double best_value = kFailedObjective;
  const ThetaBounds bounds = theta_bounds(dims, s);
  for (int start = 0; start < s.starts && !pr.stopped(); ++start) {
    nlopt::opt opt(s.optimizer == GaussianProcessOptimizer::kLbfgs ? nlopt::LD_LBFGS : nlopt::LN_BOBYQA,
                   static_cast<unsigned>(bounds.lower.size()));
    opt.set_lower_bounds(bounds.lower);
    opt.set_upper_bounds(bounds.upper);
    opt.set_min_objective(objective, const_cast<Problem*>(&pr));
    opt.set_initial_step(kInitialLogStep);
    opt.set_xtol_abs(kLogLengthTolerance);
    opt.set_maxeval(s.max_evaluations);
    std::vector<double> theta = start_point(start, dims, s);
    double value = kFailedObjective;
    try {
      opt.optimize(theta, value);
    } catch (const std::exception&) {  // roundoff_limited, forced stop: keep the last point
      if (pr.stopped()) return theta;
      std::vector<double> no_gradient;
      value = objective(theta, no_gradient, const_cast<Problem*>(&pr));
    }
    if (value < best_value || best.empty()) {
      best_value = value;
      best = theta;
    }
  }
  return best.empty() ? start_point(0, dims, s) : best;  // stopped before the first start
}

}  // namespace

double gaussian_process_objective(const DesignMatrix& u, const Eigen::VectorXd& y, KrigingTrend trend,
                                  const Eigen::VectorXd& length_scales, double nugget,
                                  Eigen::VectorXd* gradient, double* nugget_gradient) {
  const Eigen::MatrixXd f = trend_matrix(u, trend);
  const Profile p = profile(u, y, f, length_scales, nugget);
  if (gradient == nullptr && nugget_gradient == nullptr) return p.objective;
  const Eigen::MatrixXd a = p.ok ? gradient_kernel(p, u.rows()) : Eigen::MatrixXd::Zero(u.rows(), u.rows());
  if (gradient != nullptr)
    *gradient = p.ok ? objective_gradient(a, u, length_scales) : Eigen::VectorXd::Zero(u.cols());
  if (nugget_gradient != nullptr) *nugget_gradient = nugget * a.trace();
  return p.objective;
}

GaussianProcess fit_gaussian_process(const DesignMatrix& x, const Eigen::VectorXd& y,
                                     const GaussianProcessSettings& s, const std::string& name) {
  check_settings(s);
  check_data(x, y, s, name);
  GaussianProcess gp;
  gp.output_name = name;
  gp.trend = s.trend;
  gp.runs = static_cast<int>(y.size());
  gp.input_offset = x.colwise().minCoeff();
  gp.input_scale = x.colwise().maxCoeff() - gp.input_offset;
  for (Eigen::Index j = 0; j < x.cols(); ++j)
    if (!(gp.input_scale(j) > 0.0)) gp.input_scale(j) = 1.0;  // an input held constant
  gp.scaled_inputs = (x.rowwise() - gp.input_offset).array().rowwise() / gp.input_scale.array();
  const Eigen::MatrixXd f = trend_matrix(gp.scaled_inputs, s.trend);
  const Problem problem{&gp.scaled_inputs, &y, &f, s.nugget, s.estimate_nugget, s.stop};
  gp.nugget = s.nugget;
  if (s.fixed_length_scales.size() > 0) {
    gp.length_scales = s.fixed_length_scales;
  } else {
    const std::vector<double> theta = maximise_likelihood(problem, static_cast<int>(x.cols()), s);
    gp.length_scales.resize(x.cols());
    for (Eigen::Index i = 0; i < x.cols(); ++i) gp.length_scales(i) = std::exp(theta[static_cast<std::size_t>(i)]);
    if (s.estimate_nugget) gp.nugget = std::exp(theta.back());
  }
  const Profile p = profile(gp.scaled_inputs, y, f, gp.length_scales, gp.nugget);
  if (!p.ok)
    throw std::invalid_argument("Gaussian process: the correlation matrix of '" + name +
                                "' is singular at every length-scale tried (repeated runs? "
                                "try a larger nugget)");
  gp.process_variance = p.sigma2;
  gp.trend_coefficients = p.beta;
  gp.weights = p.llt.matrixU().solve(p.residual);
  gp.correlation_cholesky = p.llt.matrixL();
  gp.trend_cholesky = p.trend_llt.matrixL();
  gp.whitened_trend = p.ft;
  gp.neg_log_likelihood = p.objective;
  // Dubrule (1983): Q y = weights; Q_ii from R^-1 and the trend correction.
  const Eigen::MatrixXd l_inv = p.llt.matrixL().solve(Eigen::MatrixXd::Identity(y.size(), y.size()));
  const Eigen::MatrixXd g = l_inv.transpose() * p.ft;  // R^-1 F
  const Eigen::MatrixXd h = p.trend_llt.matrixL().solve(g.transpose());
  const Eigen::VectorXd q_diag =
      l_inv.colwise().squaredNorm().transpose() - h.colwise().squaredNorm().transpose();
  gp.loo_mean = y.array() - gp.weights.array() / q_diag.array();
  gp.loo_variance = gp.process_variance / q_diag.array();
  const double sst = (y.array() - y.mean()).square().sum();
  gp.validation.q2_loo = 1.0 - (y - gp.loo_mean).squaredNorm() / sst;
  gp.validation.training_runs = gp.runs;
  if (s.cross_validate_small_designs && s.fixed_length_scales.size() == 0 &&
      gp.runs < kGpRunsPerInputTrustedByLeaveOneOut * x.cols()) {
    GaussianProcessSettings refit = s;
    refit.cross_validate_small_designs = false;
    gp.validation.reselected = cross_validate(
        x, y, trend_terms(s.trend, x.cols()) + 2,
        [&](const DesignMatrix& x_train, const Eigen::VectorXd& y_train, const DesignMatrix& x_test) {
          return predict_gaussian_process(fit_gaussian_process(x_train, y_train, refit, name), x_test).mean;
        });
    gp.validation.reselected.refits = kGpRefits;
  }
  flag_low_q2(name, gp.runs, s.q2_threshold, &gp.validation);
  return gp;
}

GaussianProcessPrediction predict_gaussian_process(const GaussianProcess& gp, const DesignMatrix& x) {
  if (x.cols() != gp.scaled_inputs.cols())
    throw std::invalid_argument("Gaussian process: points have " + std::to_string(x.cols()) +
                                " columns, the process " + std::to_string(gp.scaled_inputs.cols()) +
                                " inputs");
  const DesignMatrix u = (x.rowwise() - gp.input_offset).array().rowwise() / gp.input_scale.array();
  const Eigen::MatrixXd f = trend_matrix(u, gp.trend);
  const Eigen::MatrixXd r = matern52_correlation(gp.scaled_inputs, u, gp.length_scales);  // n x m
  GaussianProcessPrediction out;
  out.mean = f * gp.trend_coefficients + r.transpose() * gp.weights;
  const Eigen::MatrixXd rt = gp.correlation_cholesky.triangularView<Eigen::Lower>().solve(r);
  const Eigen::MatrixXd trend_gap = f.transpose() - gp.whitened_trend.transpose() * rt;  // p x m
  const Eigen::MatrixXd trend_term = gp.trend_cholesky.triangularView<Eigen::Lower>().solve(trend_gap);
  out.variance = (gp.process_variance * (1.0 - rt.colwise().squaredNorm().array() +
                                         trend_term.colwise().squaredNorm().array()))
                     .cwiseMax(0.0)
                     .transpose();
  out.nugget_variance = gp.nugget * gp.process_variance;
  return out;
}

void validate_gaussian_process(const DesignMatrix& x_test, const Eigen::VectorXd& y_test,
                               double q2_threshold, GaussianProcess* gp) {
  score_held_out(y_test, predict_gaussian_process(*gp, x_test).mean, &gp->validation);
  flag_low_q2(gp->output_name, gp->runs, q2_threshold, &gp->validation);
}

}  // namespace rover::study
