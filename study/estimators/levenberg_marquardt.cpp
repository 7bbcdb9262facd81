// See levenberg_marquardt.hpp.
#include "study/estimators/levenberg_marquardt.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>

namespace rover::study {
namespace {

// A step is accepted when it achieves at least this share of the decrease
// its linear model predicts.
constexpr double kAcceptRatio = 1e-3;
// D's diagonal is floored at this share of its largest entry, so that a
// parameter the residuals do not (yet) depend on keeps a bounded step.
constexpr double kScalingFloor = 1e-12;

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

void check_arguments(const Eigen::VectorXd& x0, const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                     const LevenbergMarquardtSettings& s) {
  if (lower.size() != x0.size() || upper.size() != x0.size() || x0.size() == 0)
    throw std::invalid_argument("levenberg_marquardt: x0, lower and upper must have the same, non-zero size");
  for (Eigen::Index i = 0; i < x0.size(); ++i) {
    const std::string at = "levenberg_marquardt: parameter " + std::to_string(i) + ": ";
    if (!std::isfinite(x0[i])) throw std::invalid_argument(at + "start value " + number(x0[i]) + " is not finite");
    if (!(lower[i] <= upper[i])) throw std::invalid_argument(at + "lower bound above the upper bound");
    if (x0[i] < lower[i] || x0[i] > upper[i])
      throw std::invalid_argument(at + "start value " + number(x0[i]) + " outside [" + number(lower[i]) + ", " +
                                  number(upper[i]) + "]");
  }
  if (s.max_iterations < 1 || !(s.step_tolerance > 0) || !(s.gradient_tolerance > 0) ||
      !(s.decrease_tolerance > 0) || !(s.initial_damping > 0) || !(s.max_damping > s.initial_damping))
    throw std::invalid_argument(
        "levenberg_marquardt: settings need max_iterations >= 1, positive tolerances and "
        "0 < initial_damping < max_damping");
}

// The gradient J^T r with the components that point out of the box at an
// active bound set to zero (they cannot be followed).
Eigen::VectorXd projected_gradient(const Eigen::VectorXd& g, const Eigen::VectorXd& x, const Eigen::VectorXd& lower,
                                   const Eigen::VectorXd& upper) {
  Eigen::VectorXd out = g;
  for (Eigen::Index i = 0; i < g.size(); ++i)
    if ((x[i] <= lower[i] && g[i] > 0) || (x[i] >= upper[i] && g[i] < 0)) out[i] = 0;
  return out;
}

struct Iterate {
  Eigen::VectorXd x, r;
  Eigen::MatrixXd j;
  double cost = 0;
};

LevenbergMarquardtResult finish(const Iterate& it, int iterations, int evaluations, LeastSquaresStop stop,
                                const std::string& message) {
  LevenbergMarquardtResult out;
  out.x = it.x;
  out.residuals = it.r;
  out.jacobian = it.j;
  out.cost = it.cost;
  out.iterations = iterations;
  out.residual_evaluations = evaluations;
  out.stop = stop;
  out.converged = least_squares_converged(stop);
  out.message = std::string(least_squares_stop_name(stop)) + ": " + message;
  return out;
}

}  // namespace

const char* least_squares_stop_name(LeastSquaresStop stop) {
  switch (stop) {
    case LeastSquaresStop::kRelativeStep: return "relative step";
    case LeastSquaresStop::kRelativeGradient: return "relative gradient";
    case LeastSquaresStop::kRelativeDecrease: return "relative decrease";
    case LeastSquaresStop::kMaxIterations: return "iteration budget reached";
    case LeastSquaresStop::kEvaluationFailed: return "evaluation failed";
    case LeastSquaresStop::kNoProgress: return "no progress";
  }
  return "unknown";
}

bool least_squares_converged(LeastSquaresStop stop) {
  return stop == LeastSquaresStop::kRelativeStep || stop == LeastSquaresStop::kRelativeGradient ||
         stop == LeastSquaresStop::kRelativeDecrease;
}

LevenbergMarquardtResult levenberg_marquardt(const LeastSquaresResidualFunction& residuals, const LeastSquaresJacobianFunction& jacobian,
                                             const Eigen::VectorXd& x0, const Eigen::VectorXd& lower,
                                             const Eigen::VectorXd& upper, const LevenbergMarquardtSettings& s) {
  check_arguments(x0, lower, upper, s);
  Iterate it{x0, {}, {}, 0};
  int evaluations = 1, iterations = 0;
  const std::optional<Eigen::VectorXd> r0 = residuals(x0);
  if (!r0) return finish(it, 0, evaluations, LeastSquaresStop::kEvaluationFailed, "no residuals at the start point");
  it.r = *r0;
  it.cost = 0.5 * it.r.squaredNorm();
  double lambda = s.initial_damping, growth = 2.0;
  bool new_jacobian = true;
  Eigen::VectorXd g;
  Eigen::MatrixXd jtj;
  Eigen::VectorXd scaling;
  for (;;) {
    if (new_jacobian) {
      if (iterations == s.max_iterations)
        return finish(it, iterations, evaluations, LeastSquaresStop::kMaxIterations,
                      "stopped after " + std::to_string(iterations) + " iterations without meeting a tolerance");
      const std::optional<Eigen::MatrixXd> j = jacobian(it.x, it.r);
      ++iterations;
      if (!j) return finish(it, iterations, evaluations, LeastSquaresStop::kEvaluationFailed, "no Jacobian");
      it.j = *j;
      jtj = it.j.transpose() * it.j;
      g = it.j.transpose() * it.r;
      scaling = jtj.diagonal().cwiseMax(kScalingFloor * std::max(jtj.diagonal().maxCoeff(), 1e-300));
      const double gradient = projected_gradient(g, it.x, lower, upper).lpNorm<Eigen::Infinity>();
      if (gradient <= s.gradient_tolerance * std::max(1.0, it.cost))
        return finish(it, iterations, evaluations, LeastSquaresStop::kRelativeGradient,
                      "projected gradient " + number(gradient) + " at cost " + number(it.cost));
      new_jacobian = false;
    }
    // Parameters held at a bound by the gradient stay there: their rows and
    // columns leave the system (the step solves for the free ones).
    Eigen::MatrixXd a = jtj;
    a.diagonal() += lambda * scaling;
    Eigen::VectorXd rhs = -g;
    for (Eigen::Index i = 0; i < g.size(); ++i)
      if ((it.x[i] <= lower[i] && g[i] > 0) || (it.x[i] >= upper[i] && g[i] < 0)) {
        a.row(i).setZero();
        a.col(i).setZero();
        a(i, i) = 1.0;
        rhs[i] = 0.0;
      }
    Eigen::VectorXd dx = a.ldlt().solve(rhs);
    const Eigen::VectorXd trial = (it.x + dx).cwiseMax(lower).cwiseMin(upper);
    dx = trial - it.x;
    const double predicted = -(g.dot(dx) + 0.5 * (it.j * dx).squaredNorm());
    if (dx.norm() <= s.step_tolerance * (it.x.norm() + s.step_tolerance))
      return finish(it, iterations, evaluations, LeastSquaresStop::kRelativeStep,
                    "step " + number(dx.norm()) + " at |x| " + number(it.x.norm()));
    const std::optional<Eigen::VectorXd> r = residuals(trial);
    ++evaluations;
    const double cost = r ? 0.5 * r->squaredNorm() : std::numeric_limits<double>::infinity();
    const double ratio = predicted > 0 ? (it.cost - cost) / predicted : -1.0;
    if (r && std::isfinite(cost) && ratio > kAcceptRatio) {
      const double decrease = it.cost - cost;
      it.x = trial;
      it.r = *r;
      it.cost = cost;
      lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * ratio - 1.0, 3));
      growth = 2.0;
      new_jacobian = true;
      if (decrease <= s.decrease_tolerance * std::max(cost, 1e-300))
        return finish(it, iterations, evaluations, LeastSquaresStop::kRelativeDecrease,
                      "decrease " + number(decrease) + " at cost " + number(cost));
    } else {
      lambda *= growth;
      growth *= 2.0;
      if (lambda > s.max_damping)
        return finish(it, iterations, evaluations, LeastSquaresStop::kNoProgress,
                      "no acceptable step (damping " + number(lambda) + ")");
    }
  }
}

}  // namespace rover::study
