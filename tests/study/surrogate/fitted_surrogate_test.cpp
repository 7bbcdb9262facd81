// The common interface over polynomial chaos and kriging: leave-one-out
// predictions equal to refits without the run, the Gaussian process on the
// inputs' CDF values, and the kind names.
#include "study/surrogate/fitted_surrogate.hpp"

#include <numbers>

#include <gtest/gtest.h>

#include "study/estimators/test_models.hpp"
#include "surrogate_test_designs.hpp"

namespace rover::study {
namespace {

using testing::latin_hypercube;
using testing::to_inputs;

Eigen::VectorXd ishigami_values(const DesignMatrix& x) {
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = ishigami(x.row(i).data());
  return y;
}

DesignMatrix without_row(const DesignMatrix& x, Eigen::Index row) {
  DesignMatrix out(x.rows() - 1, x.cols());
  out << x.topRows(row), x.bottomRows(x.rows() - row - 1);
  return out;
}

TEST(FittedSurrogate, PolynomialChaosLeaveOneOutIsTheRefitWithoutTheRun) {
  const std::vector<Distribution> inputs(3, uniform(-std::numbers::pi, std::numbers::pi));
  const DesignMatrix x = to_inputs(latin_hypercube(120, 3, 8), inputs);
  const Eigen::VectorXd y = ishigami_values(x);
  const FittedSurrogate s = polynomial_chaos_surrogate(fit_polynomial_chaos(x, y, inputs, {}, "y"));
  const Eigen::VectorXd loo = leave_one_out_predictions(s, x, y);
  for (const Eigen::Index i : {0, 57, 119}) {
    Eigen::VectorXd y_without(y.size() - 1);
    y_without << y.head(i), y.tail(y.size() - i - 1);
    PolynomialChaosExpansion refit = s.pce;
    ASSERT_TRUE(refit_pce_coefficients(s.pce, without_row(x, i), y_without, &refit.coefficients));
    EXPECT_NEAR(loo(i), refit.evaluate(x.row(i).data()), 1e-8 * y.cwiseAbs().maxCoeff()) << i;
  }
}

TEST(FittedSurrogate, GaussianProcessWorksOnTheInputsCdfValues) {
  const std::vector<Distribution> inputs{log_uniform(1.0, 1e4), uniform(0.0, 1.0)};
  const DesignMatrix x = to_inputs(latin_hypercube(40, 2, 3), inputs);
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index i = 0; i < x.rows(); ++i) y(i) = std::log10(x(i, 0)) + std::sin(3.0 * x(i, 1));
  GaussianProcessSettings settings;
  settings.starts = 2;
  const FittedSurrogate s = fit_gaussian_process_surrogate(x, y, inputs, settings, "y");
  const DesignMatrix u = to_unit_cube(x, inputs);
  EXPECT_NEAR(u(0, 0), std::log10(x(0, 0)) / 4.0, 1e-12);  // F of a log-uniform is linear in log x
  EXPECT_EQ(s.gp.scaled_inputs.rows(), 40);
  EXPECT_GT(s.validation().q2_loo, 0.99);
  EXPECT_EQ(leave_one_out_predictions(s, x, y), s.gp.loo_mean);
  const SurrogatePrediction p = predict_surrogate(s, x);
  EXPECT_LT((p.mean - y).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_EQ(p.sd.size(), 40);
}

TEST(FittedSurrogate, KindNamesRoundTripAndUnknownOnesAreRefused) {
  for (SurrogateKind k : {SurrogateKind::kPolynomialChaos, SurrogateKind::kGaussianProcess})
    EXPECT_EQ(surrogate_kind_from_name(surrogate_kind_name(k)), k);
  EXPECT_THROW(surrogate_kind_from_name("kriging"), std::invalid_argument);
}

}  // namespace
}  // namespace rover::study
