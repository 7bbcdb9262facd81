// Kriging: interpolation of the training runs with zero predictive variance
// there, accuracy and calibrated variance on held-out points of a smooth 2-D
// function, the estimated nugget's calibration on noisy data, Dubrule's closed-form leave-one-out against refits, refused input.
#include "study/surrogate/gaussian_process.hpp"

#include <atomic>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <boost/math/distributions/normal.hpp>
#include <gtest/gtest.h>

#include "study/surrogate/matern_kernel.hpp"

#include "surrogate_test_designs.hpp"

namespace rover::study {
namespace {

using testing::latin_hypercube;

// A smooth 2-D test function on [0, 1]^2 (inputs scaled below to other ranges).
double smooth(double x1, double x2) {
  return std::sin(3.0 * x1) + std::cos(2.0 * x2) + x1 * x2 + 0.5 * x2 * x2;
}

// Inputs on [-2, 4] x [10, 11] to exercise the input scaling.
DesignMatrix physical(const DesignMatrix& u) {
  DesignMatrix x = u;
  x.col(0) = -2.0 + 6.0 * u.col(0).array();
  x.col(1) = 10.0 + u.col(1).array();
  return x;
}

Eigen::VectorXd outputs(const DesignMatrix& u) {
  Eigen::VectorXd y(u.rows());
  for (Eigen::Index r = 0; r < u.rows(); ++r) y(r) = smooth(u(r, 0), u(r, 1));
  return y;
}

TEST(GaussianProcess, AStopRequestEndsTheLikelihoodSearchAtOnce) {
  const DesignMatrix u = latin_hypercube(25, 2, 3);
  const Eigen::VectorXd y = outputs(u);
  GaussianProcessSettings s;
  const GaussianProcess searched = fit_gaussian_process(physical(u), y, s, "smooth");
  std::atomic<bool> stop{true};
  s.stop = &stop;
  const GaussianProcess stopped = fit_gaussian_process(physical(u), y, s, "smooth");
  // Stopped before its first evaluation, the fit keeps the first start's
  // length-scales: a likelihood below the searched one, but a usable model.
  EXPECT_GT(stopped.neg_log_likelihood, searched.neg_log_likelihood + 1.0);
  EXPECT_TRUE(stopped.length_scales.allFinite());
  EXPECT_TRUE(stopped.weights.allFinite());
}

TEST(GaussianProcess, InterpolatesItsTrainingRunsWithZeroVariance) {
  const DesignMatrix u = latin_hypercube(25, 2, 3);
  const Eigen::VectorXd y = outputs(u);
  GaussianProcessSettings s;
  s.nugget = 0.0;
  const GaussianProcess gp = fit_gaussian_process(physical(u), y, s, "smooth");
  const GaussianProcessPrediction p = predict_gaussian_process(gp, physical(u));
  // Away from the runs the variance is not zero.
  const GaussianProcessPrediction away =
      predict_gaussian_process(gp, physical(testing::monte_carlo(200, 2, 5)));
  const double typical_variance = away.variance.mean();
  std::printf("GP interpolation: largest error at the runs %.2e, largest variance there %.2e, "
              "mean variance elsewhere %.2e\n",
              (p.mean - y).cwiseAbs().maxCoeff(), p.variance.maxCoeff(), typical_variance);
  EXPECT_TRUE(gp.loo_mean.allFinite());
  EXPECT_TRUE((gp.loo_variance.array() > 0.0).all());
  EXPECT_GT(gp.validation.q2_loo, 0.99);
  for (Eigen::Index r = 0; r < y.size(); ++r) {
    EXPECT_NEAR(p.mean(r), y(r), 1e-7);
    EXPECT_LT(p.variance(r), 1e-4 * typical_variance);
  }
}

void expect_accurate_and_calibrated(KrigingTrend trend) {
  const DesignMatrix u = latin_hypercube(40, 2, 8);
  GaussianProcessSettings s;
  s.trend = trend;
  GaussianProcess gp = fit_gaussian_process(physical(u), outputs(u), s, "smooth");
  const DesignMatrix u_test = testing::monte_carlo(500, 2, 99);
  const Eigen::VectorXd y_test = outputs(u_test);
  const GaussianProcessPrediction p = predict_gaussian_process(gp, physical(u_test));
  const Eigen::ArrayXd z = (y_test - p.mean).array() / p.variance.array().sqrt();
  const double z_sd = std::sqrt(z.square().mean());
  validate_gaussian_process(physical(u_test), y_test, 0.95, &gp);
  std::printf("GP %s trend: length-scales %.3f %.3f, Q2 LOO %.5f, held-out Q2 %.6f, RMSE %.2e, "
              "sd of standardised errors %.3f\n",
              trend == KrigingTrend::kConstant ? "constant" : "linear", gp.length_scales(0),
              gp.length_scales(1), gp.validation.q2_loo, gp.validation.q2_test,
              gp.validation.rmse_test, z_sd);
  EXPECT_GT(gp.validation.q2_test, 0.999);
  EXPECT_GT(gp.validation.q2_loo, 0.99);
  EXPECT_TRUE(gp.validation.warning.empty());
  // On a deterministic function smoother than the Matern 5/2 paths the
  // variance is conservative (z sd ~0.45 here); it must not be overconfident.
  EXPECT_GT(z_sd, 0.25);
  EXPECT_LT(z_sd, 1.5);
  EXPECT_GT((z.abs() < 2.0).cast<double>().mean(), 0.9);
}

TEST(GaussianProcess, PredictsHeldOutPointsWithCalibratedVariance) {
  expect_accurate_and_calibrated(KrigingTrend::kConstant);
}
TEST(GaussianProcess, UniversalKrigingWithLinearTrend) {
  expect_accurate_and_calibrated(KrigingTrend::kLinear);
}

// On a sample path of a Matern 5/2 process (the model the GP assumes) the
// standardised held-out errors must have unit spread.
TEST(GaussianProcess, VarianceIsCalibratedOnAGaussianProcessSamplePath) {
  constexpr int kTrain = 50, kTest = 400;
  constexpr double kJitter = 1e-10;
  const DesignMatrix u_all = testing::monte_carlo(kTrain + kTest, 2, 314);
  Eigen::MatrixXd k = matern52_correlation(u_all, u_all, Eigen::Vector2d(0.3, 0.5));
  k.diagonal().array() += kJitter;
  const Eigen::LLT<Eigen::MatrixXd> llt(k);
  ASSERT_EQ(llt.info(), Eigen::Success);
  Eigen::VectorXd z(kTrain + kTest);
  const boost::math::normal_distribution<double> std_normal;
  for (int i = 0; i < kTrain + kTest; ++i)
    z(i) = boost::math::quantile(std_normal, testing::hashed_uniform(2718, static_cast<std::uint64_t>(i)));
  const Eigen::VectorXd path = 2.0 + 1.5 * (llt.matrixL() * z).array();
  const GaussianProcess gp = fit_gaussian_process(u_all.topRows(kTrain), path.head(kTrain), {}, "path");
  const GaussianProcessPrediction p = predict_gaussian_process(gp, u_all.bottomRows(kTest));
  const Eigen::ArrayXd standardised =
      (path.tail(kTest) - p.mean).array() / p.variance.array().sqrt();
  const double z_sd = std::sqrt(standardised.square().mean());
  std::printf("GP on a Matern sample path: length-scales %.3f %.3f (true 0.3 0.5), sigma %.3f "
              "(true 1.5), sd of standardised errors %.3f\n",
              gp.length_scales(0) * gp.input_scale(0), gp.length_scales(1) * gp.input_scale(1),
              std::sqrt(gp.process_variance), z_sd);
  EXPECT_GT(z_sd, 0.7);
  EXPECT_LT(z_sd, 1.4);
  EXPECT_NEAR((standardised.abs() < 1.96).cast<double>().mean(), 0.95, 0.06);
}

TEST(GaussianProcess, ClosedFormLeaveOneOutEqualsRefits) {
  const DesignMatrix u = latin_hypercube(15, 2, 21);
  const Eigen::VectorXd y = outputs(u);
  for (const KrigingTrend trend : {KrigingTrend::kConstant, KrigingTrend::kLinear}) {
    GaussianProcessSettings s;
    s.trend = trend;
    s.nugget = 1e-6;
    const GaussianProcess gp = fit_gaussian_process(physical(u), y, s);
    s.fixed_length_scales = gp.length_scales;
    for (int left = 0; left < 15; ++left) {
      DesignMatrix xs(14, 2);
      Eigen::VectorXd ys(14);
      for (int r = 0, k = 0; r < 15; ++r)
        if (r != left) xs.row(k) = physical(u).row(r), ys(k++) = y(r);
      GaussianProcess refit = fit_gaussian_process(xs, ys, s);
      // The refit scales its inputs by its own range: same length-scales in
      // physical units.
      refit = fit_gaussian_process(
          xs, ys, [&] {
            GaussianProcessSettings t = s;
            t.fixed_length_scales = (gp.length_scales.array() * gp.input_scale.transpose().array() /
                                     refit.input_scale.transpose().array()).matrix();
            return t;
          }());
      const GaussianProcessPrediction p = predict_gaussian_process(refit, physical(u).row(left));
      EXPECT_NEAR(gp.loo_mean(left), p.mean(0), 1e-6) << "run " << left;
      // Dubrule's variance is that of the left-out observation: it includes the nugget.
      EXPECT_NEAR(gp.loo_variance(left) / gp.process_variance,
                  p.variance(0) / refit.process_variance + s.nugget, 1e-9) << "run " << left;
    }
  }
}

TEST(GaussianProcess, AnalyticGradientMatchesFiniteDifferences) {
  const DesignMatrix u = latin_hypercube(20, 3, 17);
  Eigen::VectorXd y(20);
  for (int r = 0; r < 20; ++r) y(r) = smooth(u(r, 0), u(r, 1)) + std::sin(4.0 * u(r, 2));
  const Eigen::Vector3d ls(0.3, 0.7, 0.45);
  constexpr double kStep = 1e-6;
  for (const KrigingTrend trend : {KrigingTrend::kConstant, KrigingTrend::kLinear}) {
    Eigen::VectorXd gradient;
    gaussian_process_objective(u, y, trend, ls, 1e-6, &gradient);
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d up = ls, down = ls;
      up(k) *= std::exp(kStep);
      down(k) *= std::exp(-kStep);
      const double numeric = (gaussian_process_objective(u, y, trend, up, 1e-6, nullptr) -
                              gaussian_process_objective(u, y, trend, down, 1e-6, nullptr)) /
                             (2.0 * kStep);
      EXPECT_NEAR(gradient(k), numeric, 1e-5 * std::max(1.0, std::abs(numeric))) << "k " << k;
    }
    // With respect to log tau.
    constexpr double kNugget = 1e-3;
    double nugget_gradient = 0.0;
    gaussian_process_objective(u, y, trend, ls, kNugget, nullptr, &nugget_gradient);
    const double numeric =
        (gaussian_process_objective(u, y, trend, ls, kNugget * std::exp(kStep), nullptr) -
         gaussian_process_objective(u, y, trend, ls, kNugget * std::exp(-kStep), nullptr)) /
        (2.0 * kStep);
    EXPECT_NEAR(nugget_gradient, numeric, 1e-5 * std::max(1.0, std::abs(numeric)));
  }
}

// A smooth function observed with Gaussian noise (sd 0.05, a tenth of the
// output's spread): a fixed tiny nugget forces the process through the noise
// and its 3-sd intervals miss new observations far more often than 0.3 %;
// the estimated nugget recovers the noise level and the intervals of new
// observations (process variance plus nugget variance) hold ~99.7 % of them.
TEST(GaussianProcess, EstimatedNuggetCalibratesTheVarianceOnNoisyData) {
  constexpr int kTrain = 60, kTest = 500;
  constexpr double kNoiseSd = 0.05;
  const boost::math::normal_distribution<double> std_normal;
  const auto noisy = [&](const DesignMatrix& u, std::uint64_t seed) {
    Eigen::VectorXd y = outputs(u);
    for (Eigen::Index r = 0; r < y.size(); ++r)
      y(r) += kNoiseSd * boost::math::quantile(std_normal, testing::hashed_uniform(seed, static_cast<std::uint64_t>(r)));
    return y;
  };
  const DesignMatrix u = latin_hypercube(kTrain, 2, 41);
  const DesignMatrix u_test = testing::monte_carlo(kTest, 2, 43);
  const Eigen::VectorXd y = noisy(u, 45), y_test = noisy(u_test, 47);
  const auto coverage = [&](const GaussianProcess& gp) {
    const GaussianProcessPrediction p = predict_gaussian_process(gp, physical(u_test));
    const Eigen::ArrayXd sd = (p.variance.array() + p.nugget_variance).sqrt();
    return ((y_test - p.mean).array().abs() <= 3.0 * sd).cast<double>().mean();
  };
  GaussianProcessSettings s;
  const GaussianProcess fixed = fit_gaussian_process(physical(u), y, s, "noisy");
  s.estimate_nugget = true;
  const GaussianProcess estimated = fit_gaussian_process(physical(u), y, s, "noisy");
  const double noise_sd = std::sqrt(estimated.nugget * estimated.process_variance);
  std::printf("GP on noisy data: 3-sd coverage of new observations %.3f (fixed nugget 1e-8), %.3f "
              "(estimated nugget %.2e, noise sd %.4f, true %.4f)\n",
              coverage(fixed), coverage(estimated), estimated.nugget, noise_sd, kNoiseSd);
  EXPECT_LT(coverage(fixed), 0.95);
  EXPECT_GT(coverage(estimated), 0.98);
  EXPECT_NEAR(noise_sd, kNoiseSd, 0.3 * kNoiseSd);
}

TEST(GaussianProcess, LbfgsWithGradientReachesTheBobyqaOptimum) {
  const DesignMatrix u = latin_hypercube(40, 2, 8);
  GaussianProcessSettings s;
  const GaussianProcess bobyqa = fit_gaussian_process(physical(u), outputs(u), s);
  s.optimizer = GaussianProcessOptimizer::kLbfgs;
  const GaussianProcess lbfgs = fit_gaussian_process(physical(u), outputs(u), s);
  EXPECT_NEAR(lbfgs.neg_log_likelihood, bobyqa.neg_log_likelihood, 1e-3);
  EXPECT_NEAR(lbfgs.validation.q2_loo, bobyqa.validation.q2_loo, 1e-4);
}

std::string thrown_message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

TEST(GaussianProcess, RefusesBadSettingsAndData) {
  const DesignMatrix u = latin_hypercube(10, 2, 1);
  const Eigen::VectorXd y = outputs(u);
  GaussianProcessSettings s;
  s.nugget = -1.0;
  EXPECT_NE(thrown_message([&] { fit_gaussian_process(u, y, s); }).find("nugget -1 is outside [0, 0.1]"),
            std::string::npos);
  s = {};
  s.starts = 0;
  EXPECT_NE(thrown_message([&] { fit_gaussian_process(u, y, s); }).find("starts 0"), std::string::npos);
  s = {};
  s.min_length_scale = 2.0;
  s.max_length_scale = 1.0;
  EXPECT_NE(thrown_message([&] { fit_gaussian_process(u, y, s); }).find("length-scale bounds"),
            std::string::npos);
  s = {};
  s.fixed_length_scales = Eigen::VectorXd::Ones(3);
  EXPECT_NE(thrown_message([&] { fit_gaussian_process(u, y, s); }).find("fixed_length_scales"),
            std::string::npos);
  s = {};
  s.trend = KrigingTrend::kLinear;
  EXPECT_NE(thrown_message([&] { fit_gaussian_process(u.topRows(4), y.head(4), s, "q"); })
                .find("needs at least 5"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { fit_gaussian_process(u, y.head(9), {}); }).find("10 x 2"),
            std::string::npos);
  Eigen::VectorXd failed = y;
  failed(4) = std::nan("");
  EXPECT_NE(thrown_message([&] { fit_gaussian_process(u, failed, {}, "slip"); }).find("at run 4"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { fit_gaussian_process(u, Eigen::VectorXd::Constant(10, 1.0), {}, "flat"); })
                .find("'flat' is constant"),
            std::string::npos);
  const GaussianProcess gp = fit_gaussian_process(u, y, {});
  EXPECT_THROW(predict_gaussian_process(gp, DesignMatrix::Zero(2, 3)), std::invalid_argument);
}

}  // namespace
}  // namespace rover::study
