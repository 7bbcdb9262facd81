// Levenberg-Marquardt (study/estimators/levenberg_marquardt.cpp) against
// certified answers: NIST StRD Misra1a, Rosenbrock as least squares, an
// optimum on a bound; and the stopping rules that say "not converged".
#include "study/estimators/levenberg_marquardt.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <gtest/gtest.h>

namespace rover::study {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// NIST StRD nonlinear regression, Misra1a: y = b1 (1 - exp(-b2 x)).
const double kMisraX[] = {77.6, 114.9, 141.1, 190.8, 239.9, 289.0, 332.8,
                          378.4, 434.8, 477.3, 536.8, 593.1, 689.1, 760.0};
const double kMisraY[] = {10.07, 14.73, 17.94, 23.93, 29.61, 35.18, 40.02,
                          44.82, 50.76, 55.05, 61.01, 66.40, 75.47, 81.78};
constexpr double kMisraB1 = 2.3894212918e+02, kMisraB2 = 5.5015643181e-04;

std::optional<Eigen::VectorXd> misra_residuals(const Eigen::VectorXd& b) {
  Eigen::VectorXd r(14);
  for (int i = 0; i < 14; ++i) r[i] = b[0] * (1.0 - std::exp(-b[1] * kMisraX[i])) - kMisraY[i];
  return r;
}

std::optional<Eigen::MatrixXd> misra_jacobian(const Eigen::VectorXd& b, const Eigen::VectorXd&) {
  Eigen::MatrixXd j(14, 2);
  for (int i = 0; i < 14; ++i) {
    j(i, 0) = 1.0 - std::exp(-b[1] * kMisraX[i]);
    j(i, 1) = b[0] * kMisraX[i] * std::exp(-b[1] * kMisraX[i]);
  }
  return j;
}

// A central-difference Jacobian, as a caller with simulated residuals makes it.
LeastSquaresJacobianFunction central_differences(const LeastSquaresResidualFunction& f) {
  return [f](const Eigen::VectorXd& x, const Eigen::VectorXd& r) -> std::optional<Eigen::MatrixXd> {
    Eigen::MatrixXd j(r.size(), x.size());
    for (Eigen::Index c = 0; c < x.size(); ++c) {
      const double h = 1e-6 * std::max(std::abs(x[c]), 1e-8);
      Eigen::VectorXd plus = x, minus = x;
      plus[c] += h;
      minus[c] -= h;
      j.col(c) = (*f(plus) - *f(minus)) / (2 * h);
    }
    return j;
  };
}

Eigen::VectorXd unbounded(int n, double sign) { return Eigen::VectorXd::Constant(n, sign * kInf); }

TEST(LevenbergMarquardt, Misra1aFromBothNistStartsReachesTheCertifiedValues) {
  for (const Eigen::Vector2d start : {Eigen::Vector2d(500, 1e-4), Eigen::Vector2d(250, 5e-4)}) {
    const LevenbergMarquardtResult fit =
        levenberg_marquardt(misra_residuals, misra_jacobian, start, unbounded(2, -1), unbounded(2, 1));
    EXPECT_TRUE(fit.converged) << fit.message;
    EXPECT_NEAR(fit.x[0] / kMisraB1, 1.0, 1e-6) << fit.message;
    EXPECT_NEAR(fit.x[1] / kMisraB2, 1.0, 1e-6) << fit.message;
    // NIST's certified residual sum of squares: 1.2455138894E-01.
    EXPECT_NEAR(2 * fit.cost, 1.2455138894e-01, 1e-8);
  }
}

TEST(LevenbergMarquardt, FiniteDifferenceJacobianConvergesToo) {
  const LevenbergMarquardtResult fit = levenberg_marquardt(
      misra_residuals, central_differences(misra_residuals), Eigen::Vector2d(500, 1e-4), unbounded(2, -1),
      unbounded(2, 1));
  EXPECT_TRUE(fit.converged) << fit.message;
  EXPECT_NEAR(fit.x[0] / kMisraB1, 1.0, 1e-5);
  EXPECT_NEAR(fit.x[1] / kMisraB2, 1.0, 1e-5);
}

std::optional<Eigen::VectorXd> rosenbrock(const Eigen::VectorXd& x) {
  return Eigen::Vector2d(10 * (x[1] - x[0] * x[0]), 1 - x[0]).eval();
}

TEST(LevenbergMarquardt, RosenbrockValleyReachesOneOne) {
  const LevenbergMarquardtResult fit = levenberg_marquardt(rosenbrock, central_differences(rosenbrock),
                                                           Eigen::Vector2d(-1.2, 1), unbounded(2, -1), unbounded(2, 1));
  EXPECT_TRUE(fit.converged) << fit.message;
  EXPECT_NEAR(fit.x[0], 1.0, 1e-6);
  EXPECT_NEAR(fit.x[1], 1.0, 1e-6);
}

TEST(LevenbergMarquardt, OptimumOnABoundStopsOnTheProjectedGradient) {
  // The unconstrained optimum (1, 1) lies beyond x0 <= 0.5; the constrained
  // one is (0.5, 0.25), where the gradient points out of the box.
  const LevenbergMarquardtResult fit =
      levenberg_marquardt(rosenbrock, central_differences(rosenbrock), Eigen::Vector2d(-1.2, 1),
                          Eigen::Vector2d(-2, -2), Eigen::Vector2d(0.5, 2));
  EXPECT_TRUE(fit.converged) << fit.message;
  EXPECT_DOUBLE_EQ(fit.x[0], 0.5);
  EXPECT_NEAR(fit.x[1], 0.25, 1e-6);
}

TEST(LevenbergMarquardt, SmallBudgetIsReportedAsNotConverged) {
  LevenbergMarquardtSettings settings;
  settings.max_iterations = 2;
  const LevenbergMarquardtResult fit = levenberg_marquardt(misra_residuals, misra_jacobian, Eigen::Vector2d(500, 1e-4),
                                                           unbounded(2, -1), unbounded(2, 1), settings);
  EXPECT_FALSE(fit.converged);
  EXPECT_EQ(fit.stop, LeastSquaresStop::kMaxIterations);
  EXPECT_NE(fit.message.find("iteration budget"), std::string::npos) << fit.message;
  EXPECT_EQ(fit.iterations, 2);
}

TEST(LevenbergMarquardt, FailedTrialPointsAreRejectedNotFatal) {
  // Residuals fail for b2 > 2e-3, where the first undamped steps go.
  int failures = 0;
  const LeastSquaresResidualFunction fragile = [&](const Eigen::VectorXd& b) -> std::optional<Eigen::VectorXd> {
    if (b[1] > 2e-3) {
      ++failures;
      return std::nullopt;
    }
    return misra_residuals(b);
  };
  LevenbergMarquardtSettings settings;
  settings.initial_damping = 1e-9;  // bold first steps
  const LevenbergMarquardtResult fit = levenberg_marquardt(fragile, misra_jacobian, Eigen::Vector2d(500, 1e-4),
                                                           unbounded(2, -1), unbounded(2, 1), settings);
  EXPECT_TRUE(fit.converged) << fit.message;
  EXPECT_NEAR(fit.x[1] / kMisraB2, 1.0, 1e-6);

  const LeastSquaresResidualFunction broken = [](const Eigen::VectorXd&) -> std::optional<Eigen::VectorXd> {
    return std::nullopt;
  };
  const LevenbergMarquardtResult none =
      levenberg_marquardt(broken, misra_jacobian, Eigen::Vector2d(500, 1e-4), unbounded(2, -1), unbounded(2, 1));
  EXPECT_FALSE(none.converged);
  EXPECT_EQ(none.stop, LeastSquaresStop::kEvaluationFailed);
}

TEST(LevenbergMarquardt, RunsAreBitIdentical) {
  const auto run = [] {
    return levenberg_marquardt(misra_residuals, central_differences(misra_residuals), Eigen::Vector2d(500, 1e-4),
                               unbounded(2, -1), unbounded(2, 1));
  };
  const LevenbergMarquardtResult a = run(), b = run();
  EXPECT_EQ(a.x[0], b.x[0]);
  EXPECT_EQ(a.x[1], b.x[1]);
  EXPECT_EQ(a.residual_evaluations, b.residual_evaluations);
}

TEST(LevenbergMarquardt, StartOutsideTheBoxIsRefusedByIndex) {
  try {
    levenberg_marquardt(misra_residuals, misra_jacobian, Eigen::Vector2d(500, 1e-4), Eigen::Vector2d(0, 2e-4),
                        Eigen::Vector2d(1000, 1));
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("parameter 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rover::study
