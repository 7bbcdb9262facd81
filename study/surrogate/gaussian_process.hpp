// Gaussian-process regression (kriging) of a scalar output (Rasmussen &
// Williams 2006; Santner, Williams & Notz 2003):
//   Y(x) = f(x)^T beta + Z(x),  Cov(Z(x), Z(x')) = sigma^2 (k(x, x') + tau delta_xx'),
// with a constant (ordinary kriging) or linear (universal kriging) trend f,
// the anisotropic Matern 5/2 correlation k (matern_kernel.hpp) on the inputs
// scaled to [0, 1] by their training range, and a relative nugget tau: fixed
// and small (the process interpolates its runs), or estimated by maximum
// likelihood with the length-scales when the output is noisy, like a wall
// time, or rougher than the kernel at the scale of the runs (Rasmussen &
// Williams 2006, sec. 2.2 and 5.4.1; Andrianakis & Challenor 2012). A fixed
// tiny nugget on such an output makes the predictive sd too small.
//
// beta is the generalised least-squares estimate and sigma^2 is profiled out
// in closed form, sigma^2 = (y - F beta)^T R^-1 (y - F beta) / n, so the
// likelihood is maximised over the log length-scales alone:
//   min  n log sigma^2(theta) + log det R(theta)
// by NLopt's BOBYQA (Powell 2009) or L-BFGS with the analytic gradient, in a
// box, from several deterministic starts.
//
// Prediction (universal kriging, Santner et al. 2003, sec. 3.2):
//   m(x)   = f^T beta + r^T R^-1 (y - F beta)
//   s^2(x) = sigma^2 (1 - r^T R^-1 r + u^T (F^T R^-1 F)^-1 u),  u = f - F^T R^-1 r,
// the last term being the uncertainty of the estimated trend. Leave-one-out
// residuals and variances in closed form (Dubrule 1983), at the fitted
// hyperparameters and with the trend re-estimated:
//   Q = R^-1 - R^-1 F (F^T R^-1 F)^-1 F^T R^-1,  e_i = (Q y)_i / Q_ii,  s_i^2 = sigma^2 / Q_ii.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"
#include "study/surrogate/surrogate_validation.hpp"

namespace rover::study {

enum class KrigingTrend { kConstant, kLinear };
// kBobyqa: derivative-free (Powell 2009). kLbfgs: NLopt's LD_LBFGS (Liu &
// Nocedal 1989) with the analytic gradient of the concentrated likelihood.
enum class GaussianProcessOptimizer { kBobyqa, kLbfgs };

struct GaussianProcessSettings {
  KrigingTrend trend = KrigingTrend::kConstant;
  GaussianProcessOptimizer optimizer = GaussianProcessOptimizer::kBobyqa;
  double nugget = 1e-8;            // tau, relative to sigma^2: [0, 0.1]; the start when estimated
  // Estimate tau by maximum likelihood in [min_nugget, max_nugget] with the length-scales.
  bool estimate_nugget = false;
  double min_nugget = 1e-10;       // > 0
  double max_nugget = 0.1;         // > min_nugget, <= 10: an output noisier than its trend has nothing to krige
  int starts = 4;                  // optimiser starts: 1 .. 100
  int max_evaluations = 500;       // likelihood evaluations per start: >= 10
  // Bounds of the length-scales on the inputs scaled to [0, 1]: 0 < min < max.
  double min_length_scale = 0.01;
  double max_length_scale = 20.0;
  std::uint64_t seed = 1;          // the starts after the first depend on it
  // Non-empty: these length-scales (in the scaled units, one per input, > 0)
  // are used as they are and the likelihood is not maximised (the nugget is
  // then the fixed one).
  Eigen::VectorXd fixed_length_scales;
  double q2_threshold = kDefaultQ2Threshold;
  // When set and true (a signal arrived), the likelihood's maximisation stops
  // at its next evaluation and the fit returns at once; its result is
  // incomplete, for a caller that discards it.
  const std::atomic<bool>* stop = nullptr;
  // On fewer runs than kGpRunsPerInputTrustedByLeaveOneOut per input, score
  // the whole fit by a cross-validation that estimates the length-scales
  // afresh in each fold (validation.reselected): leave-one-out keeps the
  // length-scales fitted to all the runs and, on so few, flatters the
  // process. false: leave-one-out only.
  bool cross_validate_small_designs = true;
};

// Loeppky, Sacks & Welch (2009) recommend 10 runs per input for a computer
// experiment's Gaussian process; on fewer, the estimated length-scales, and
// the leave-one-out Q^2 that keeps them, are not to be taken at their word.
inline constexpr int kGpRunsPerInputTrustedByLeaveOneOut = 10;
// What a fold of the cross-validation fits afresh (CrossValidation::refits).
inline constexpr const char* kGpRefits = "length-scales re-estimated";

struct GaussianProcess {
  std::string output_name;
  KrigingTrend trend = KrigingTrend::kConstant;
  Eigen::RowVectorXd input_offset, input_scale;  // u = (x - offset) / scale
  DesignMatrix scaled_inputs;                    // training points in u
  Eigen::VectorXd length_scales;                 // in u units, one per input
  double process_variance = 0.0;                 // sigma^2
  double nugget = 0.0;                           // tau
  Eigen::VectorXd trend_coefficients;            // beta (in u units for the linear trend)
  Eigen::VectorXd weights;                       // R^-1 (y - F beta)
  Eigen::MatrixXd correlation_cholesky;          // lower L, R = L L^T
  Eigen::MatrixXd trend_cholesky;                // lower L_F, F^T R^-1 F = L_F L_F^T
  Eigen::MatrixXd whitened_trend;                // L^-1 F
  double neg_log_likelihood = 0.0;               // n log sigma^2 + log det R, at the optimum
  // Dubrule's LOO prediction of each run, and the variance of its error
  // (that of the left-out observation: the nugget tau sigma^2 included).
  Eigen::VectorXd loo_mean, loo_variance;
  int runs = 0;
  SurrogateValidation validation;                // q2_loo from loo_mean
};

// variance: of the process's mean at each point (0 at a run when the nugget
// is 0). An observation at the point adds the nugget's variance, tau sigma^2,
// the same everywhere.
struct GaussianProcessPrediction {
  Eigen::VectorXd mean, variance;  // one per point; variance >= 0
  double nugget_variance = 0.0;    // tau sigma^2
};

// Throws std::invalid_argument naming the setting, its value and the accepted
// range for bad settings, and for: x not runs x inputs with y one value per
// run, fewer runs than the trend needs plus 2 (constant: 3, linear: d + 3), a
// non-finite x or y (naming the run), or a constant y (nothing to fit).
GaussianProcess fit_gaussian_process(const DesignMatrix& x, const Eigen::VectorXd& y,
                                     const GaussianProcessSettings& settings,
                                     const std::string& output_name = "output");

// The minimised objective n log sigma^2 + log det R at these length-scales,
// on inputs u already scaled (as GaussianProcess::scaled_inputs), and its
// gradient with respect to the log length-scales if gradient is not null
// (Rasmussen & Williams 2006, eq. 5.9, with sigma^2 and beta profiled out);
// with nugget_gradient not null, also its derivative with respect to log tau.
// 1e300 (and a zero gradient) where R is not positive definite.
double gaussian_process_objective(const DesignMatrix& u, const Eigen::VectorXd& y, KrigingTrend trend,
                                  const Eigen::VectorXd& length_scales, double nugget,
                                  Eigen::VectorXd* gradient, double* nugget_gradient = nullptr);

// Predictive mean and variance at the rows of x (physical units).
GaussianProcessPrediction predict_gaussian_process(const GaussianProcess& gp,
                                                   const DesignMatrix& x);

// Scores the process on held-out runs and refreshes its warning.
void validate_gaussian_process(const DesignMatrix& x_test, const Eigen::VectorXd& y_test,
                               double q2_threshold, GaussianProcess* gp);

}  // namespace rover::study
