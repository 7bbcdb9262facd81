// Bounded Levenberg-Marquardt least squares that says whether it converged
// and why it stopped (Madsen, Nielsen & Tingleff 2004, "Methods for
// non-linear least squares problems", §3.2; Marquardt 1963 for the scaled
// damping).
//
// Minimises 0.5 ||r(x)||^2 over a box. The residuals and the Jacobian come
// from callbacks, so a caller whose residuals are simulations can compute the
// Jacobian by finite differences in parallel. Each step solves
// (J^T J + lambda D) dx = -J^T r, D = diag(J^T J) floored, by a Cholesky
// (LDL^T) factorization: the normal equations are well conditioned by the
// damping and p is small. Parameters held at a bound by the gradient are left
// out of the step, and the trial point is projected onto the box; the
// gain ratio compares the actual decrease with that of the linear model for
// the projected step, and lambda follows Nielsen's update. Stopping rules:
// a relative step, a relative projected gradient, a relative decrease (these
// count as converged) or the iteration budget, a failed evaluation, or no
// acceptable step (these do not). Deterministic: the same inputs give
// bit-identical results, so MPI ranks can run it in lockstep.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <Eigen/Core>

namespace rover::study {

enum class LeastSquaresStop {
  kRelativeStep,      // converged: ||dx|| <= step_tolerance (||x|| + step_tolerance)
  kRelativeGradient,  // converged: ||projected J^T r||_inf <= gradient_tolerance max(1, cost)
  kRelativeDecrease,  // converged: an accepted step decreased the cost by < decrease_tolerance cost
  kMaxIterations,     // not converged: the iteration budget ran out
  kEvaluationFailed,  // not converged: no residuals or Jacobian at the current point
  kNoProgress,        // not converged: the damping grew past max_damping without an acceptable step
};
const char* least_squares_stop_name(LeastSquaresStop stop);  // "relative step", ...
bool least_squares_converged(LeastSquaresStop stop);

struct LevenbergMarquardtSettings {
  int max_iterations = 100;  // Jacobian evaluations at most
  double step_tolerance = 1e-6;
  double gradient_tolerance = 1e-8;
  double decrease_tolerance = 1e-10;
  double initial_damping = 1e-3;  // lambda, relative to D
  double max_damping = 1e16;
};

struct LevenbergMarquardtResult {
  Eigen::VectorXd x;          // the last accepted point
  Eigen::VectorXd residuals;  // at x
  Eigen::MatrixXd jacobian;   // at x (empty if none was evaluated)
  double cost = 0;            // 0.5 ||r||^2 at x
  int iterations = 0;         // Jacobian evaluations
  int residual_evaluations = 0;
  LeastSquaresStop stop = LeastSquaresStop::kMaxIterations;
  bool converged = false;
  std::string message;  // why it stopped, with the numbers
};

// Residuals at x; std::nullopt where they cannot be evaluated.
using LeastSquaresResidualFunction = std::function<std::optional<Eigen::VectorXd>(const Eigen::VectorXd& x)>;
// Jacobian (n x p) at x, given the residuals r there; std::nullopt on failure.
using LeastSquaresJacobianFunction =
    std::function<std::optional<Eigen::MatrixXd>(const Eigen::VectorXd& x, const Eigen::VectorXd& r)>;

// Throws std::invalid_argument for mismatched sizes, lower > upper, x0
// outside the box or not finite (naming the index), or bad settings.
LevenbergMarquardtResult levenberg_marquardt(const LeastSquaresResidualFunction& residuals, const LeastSquaresJacobianFunction& jacobian,
                                             const Eigen::VectorXd& x0, const Eigen::VectorXd& lower,
                                             const Eigen::VectorXd& upper,
                                             const LevenbergMarquardtSettings& settings = {});

}  // namespace rover::study
