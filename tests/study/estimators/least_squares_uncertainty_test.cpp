// Least-squares uncertainty (study/estimators/least_squares_uncertainty.cpp): the
// textbook straight-line formulas, interval coverage over noise seeds, rank
// deficiency, finite-difference steps and profile-likelihood intervals.
#include "study/estimators/least_squares_uncertainty.hpp"

#include <cmath>
#include <iostream>
#include <limits>
#include <stdexcept>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <gtest/gtest.h>

namespace rover::study {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Ordinary least squares of y = a + b x in closed form; the residuals
// r = y - a - b x and their Jacobian d r / d(a, b) = -[1, x].
struct LineFit {
  Eigen::Vector2d parameters;
  Eigen::VectorXd residuals;
  Eigen::MatrixXd jacobian;
  double x_mean = 0, sxx = 0;
};
LineFit fit_line(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  LineFit f;
  f.x_mean = x.mean();
  const Eigen::VectorXd dx = x.array() - f.x_mean;
  f.sxx = dx.squaredNorm();
  const double b = dx.dot(y) / f.sxx;
  const double a = y.mean() - b * f.x_mean;
  f.parameters << a, b;
  f.residuals = y.array() - a - b * x.array();
  f.jacobian.resize(x.size(), 2);
  f.jacobian.col(0).setConstant(-1.0);
  f.jacobian.col(1) = -x;
  return f;
}

Eigen::VectorXd noisy_line(const Eigen::VectorXd& x, double a, double b, double noise_sd, std::uint64_t seed) {
  boost::random::mt19937_64 engine(seed);
  boost::random::normal_distribution<double> noise(0.0, noise_sd);
  Eigen::VectorXd y(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) y[i] = a + b * x[i] + noise(engine);
  return y;
}

TEST(GaussNewtonUncertainty, StraightLineMatchesTextbookFormulas) {
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(20, 0.0, 19.0);
  const LineFit f = fit_line(x, noisy_line(x, 2.0, 0.5, 0.4, 1));
  const LeastSquaresUncertainty u = gauss_newton_uncertainty(f.parameters, f.residuals, f.jacobian);
  const double s2 = f.residuals.squaredNorm() / 18.0;
  EXPECT_EQ(u.degrees_of_freedom, 18);
  EXPECT_EQ(u.rank, 2);
  EXPECT_NEAR(u.noise_sd, std::sqrt(s2), 1e-14);
  // sigma^2 (X^T X)^-1 for X = [1, x]: var b = s^2/Sxx, var a = s^2 (1/n + xbar^2/Sxx), cov = -xbar s^2/Sxx.
  EXPECT_NEAR(u.covariance(1, 1), s2 / f.sxx, 1e-12 * s2 / f.sxx);
  EXPECT_NEAR(u.covariance(0, 0), s2 * (1.0 / 20.0 + f.x_mean * f.x_mean / f.sxx), 1e-12 * s2);
  EXPECT_NEAR(u.covariance(0, 1), -f.x_mean * s2 / f.sxx, 1e-12 * s2);
  EXPECT_NEAR(u.covariance(1, 0), u.covariance(0, 1), 1e-15);
  // corr(a, b) = -xbar / sqrt(Sxx / n + xbar^2)
  EXPECT_NEAR(u.correlation(0, 1), -f.x_mean / std::sqrt(f.sxx / 20.0 + f.x_mean * f.x_mean), 1e-12);
  EXPECT_DOUBLE_EQ(u.correlation(0, 0), 1.0);
  // Student t, 18 degrees of freedom, 97.5 % quantile: 2.10092204024096.
  for (Eigen::Index j = 0; j < 2; ++j) {
    EXPECT_NEAR(u.standard_error[j], std::sqrt(u.covariance(j, j)), 1e-15);
    EXPECT_NEAR(u.upper[j] - f.parameters[j], 2.10092204024096 * u.standard_error[j], 1e-12);
    EXPECT_NEAR(f.parameters[j] - u.lower[j], 2.10092204024096 * u.standard_error[j], 1e-12);
  }
  EXPECT_TRUE(u.warning.empty()) << u.warning;
}

TEST(GaussNewtonUncertainty, FewDegreesOfFreedomUseTheStudentQuantile) {
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(4, 0.0, 3.0);
  const LineFit f = fit_line(x, noisy_line(x, 1.0, -1.0, 0.1, 2));
  const LeastSquaresUncertainty u = gauss_newton_uncertainty(f.parameters, f.residuals, f.jacobian, 0.95);
  EXPECT_EQ(u.degrees_of_freedom, 2);
  // With 2 degrees of freedom the t quantile is closed-form: t_q = (2q - 1) / sqrt(2 q (1 - q)).
  const auto t2 = [](double q) { return (2.0 * q - 1.0) / std::sqrt(2.0 * q * (1.0 - q)); };
  EXPECT_NEAR(u.upper[1] - f.parameters[1], t2(0.975) * u.standard_error[1], 1e-12);
  const LeastSquaresUncertainty u90 = gauss_newton_uncertainty(f.parameters, f.residuals, f.jacobian, 0.90);
  EXPECT_NEAR(u90.upper[1] - f.parameters[1], t2(0.95) * u90.standard_error[1], 1e-12);
}

TEST(GaussNewtonUncertainty, IntervalsCoverTheTruthAtTheNominalRate) {
  // 400 noise seeds, n = 8 (6 degrees of freedom, where t and normal quantiles differ by 25 %).
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(8, -1.0, 2.5);
  const Eigen::Vector2d truth(0.3, 1.7);
  int covered_a = 0, covered_b = 0;
  const int trials = 400;
  for (int seed = 0; seed < trials; ++seed) {
    const LineFit f = fit_line(x, noisy_line(x, truth[0], truth[1], 0.2, 1000 + static_cast<std::uint64_t>(seed)));
    const LeastSquaresUncertainty u = gauss_newton_uncertainty(f.parameters, f.residuals, f.jacobian, 0.95);
    covered_a += (u.lower[0] <= truth[0] && truth[0] <= u.upper[0]) ? 1 : 0;
    covered_b += (u.lower[1] <= truth[1] && truth[1] <= u.upper[1]) ? 1 : 0;
  }
  const double rate_a = covered_a / static_cast<double>(trials), rate_b = covered_b / static_cast<double>(trials);
  std::cout << "95 % interval coverage over " << trials << " seeds: a " << rate_a << ", b " << rate_b << "\n";
  // Binomial sd sqrt(0.95 * 0.05 / 400) = 0.0109; 3 sd either side.
  EXPECT_NEAR(rate_a, 0.95, 3.0 * 0.0109);
  EXPECT_NEAR(rate_b, 0.95, 3.0 * 0.0109);
}

TEST(GaussNewtonUncertainty, ColumnScalingDoesNotChangeTheAnswer) {
  // Parameters in units 1e6 and 1e-6 times larger: cov' = D^-1 cov D^-1 for J' = J D.
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(30, 0.0, 1.0);
  const LineFit f = fit_line(x, noisy_line(x, 2.0, -3.0, 0.05, 3));
  const Eigen::Vector2d d(1e6, 1e-6);
  const LeastSquaresUncertainty u = gauss_newton_uncertainty(f.parameters, f.residuals, f.jacobian);
  const LeastSquaresUncertainty scaled = gauss_newton_uncertainty(
      f.parameters.cwiseQuotient(d), f.residuals, f.jacobian * d.asDiagonal());
  for (Eigen::Index i = 0; i < 2; ++i) {
    EXPECT_NEAR(scaled.standard_error[i] * d[i], u.standard_error[i], 1e-10 * u.standard_error[i]);
    EXPECT_NEAR(scaled.lower[i] * d[i], u.lower[i], 1e-10 * std::abs(u.lower[i]));
  }
  EXPECT_NEAR(scaled.correlation(0, 1), u.correlation(0, 1), 1e-12);
  EXPECT_NEAR(scaled.condition_number, u.condition_number, 1e-10 * u.condition_number);
  EXPECT_TRUE(scaled.warning.empty()) << scaled.warning;
}

TEST(GaussNewtonUncertainty, DuplicatedColumnIsRankDeficient) {
  // r = y - (c_q + f) x - offset: only c_q + f is identifiable; offset still is.
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(12, 0.0, 11.0);
  const LineFit line = fit_line(x, noisy_line(x, 1.0, 0.25, 0.1, 4));
  Eigen::MatrixXd jacobian(12, 3);
  jacobian.col(0) = -x;
  jacobian.col(1) = -x;
  jacobian.col(2).setConstant(-1.0);
  const Eigen::Vector3d parameters(0.125, 0.125, line.parameters[0]);
  const LeastSquaresUncertainty u =
      gauss_newton_uncertainty(parameters, line.residuals, jacobian, 0.95, {"c_q", "f", "offset"});
  EXPECT_EQ(u.rank, 2);
  EXPECT_EQ(u.degrees_of_freedom, 10);
  EXPECT_NE(u.warning.find("rank deficient"), std::string::npos) << u.warning;
  EXPECT_NE(u.warning.find("c_q and f are not separately identifiable"), std::string::npos) << u.warning;
  EXPECT_EQ(u.standard_error[0], kInf);
  EXPECT_EQ(u.standard_error[1], kInf);
  EXPECT_EQ(u.lower[0], -kInf);
  EXPECT_EQ(u.upper[1], kInf);
  EXPECT_TRUE(std::isnan(u.correlation(0, 2)));
  // The offset is estimable: same standard error as in the well-posed line fit.
  const LeastSquaresUncertainty reference = gauss_newton_uncertainty(line.parameters, line.residuals, line.jacobian);
  EXPECT_NEAR(u.standard_error[2], reference.standard_error[0], 1e-10 * reference.standard_error[0]);
}

TEST(GaussNewtonUncertainty, ZeroColumnIsNamed) {
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(10, 1.0, 10.0);
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(10, 2);
  jacobian.col(0) = -x;
  const Eigen::VectorXd residuals = noisy_line(x, 0.0, 0.0, 0.1, 5);
  const LeastSquaresUncertainty u =
      gauss_newton_uncertainty(Eigen::Vector2d(0.2, 3.0), residuals, jacobian, 0.95, {"c_q", "f"});
  EXPECT_EQ(u.rank, 1);
  EXPECT_NE(u.warning.find("f is not identifiable"), std::string::npos) << u.warning;
  EXPECT_NE(u.warning.find("f has no effect"), std::string::npos) << u.warning;
  // c_q alone: var = s^2 / sum x^2 with s^2 = RSS / (n - 1).
  EXPECT_NEAR(u.standard_error[0], std::sqrt(residuals.squaredNorm() / 9.0 / x.squaredNorm()), 1e-14);
  EXPECT_EQ(u.standard_error[1], kInf);
}

TEST(GaussNewtonUncertainty, NearlyCollinearColumnsAreReported) {
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(10, 1.0, 2.0);
  Eigen::MatrixXd jacobian(10, 2);
  jacobian.col(0) = x;
  jacobian.col(1) = x + 1e-3 * x.array().square().matrix();
  const LeastSquaresUncertainty u = gauss_newton_uncertainty(Eigen::Vector2d(1, 1), noisy_line(x, 0, 0, 0.1, 6),
                                                             jacobian, 0.95, {"c_q", "f"});
  EXPECT_EQ(u.rank, 2);
  EXPECT_GT(std::abs(u.correlation(0, 1)), 0.99);
  EXPECT_NE(u.warning.find("c_q and f are strongly correlated"), std::string::npos) << u.warning;
}

TEST(GaussNewtonUncertainty, RejectsBadInput) {
  const Eigen::MatrixXd j = Eigen::MatrixXd::Random(5, 2);
  EXPECT_THROW(gauss_newton_uncertainty(Eigen::Vector2d(1, 1), Eigen::VectorXd::Ones(2), j.topRows(2)),
               std::invalid_argument);  // n <= p
  EXPECT_THROW(gauss_newton_uncertainty(Eigen::Vector2d(1, 1), Eigen::VectorXd::Ones(4), j), std::invalid_argument);
  EXPECT_THROW(gauss_newton_uncertainty(Eigen::Vector2d(1, 1), Eigen::VectorXd::Ones(5), j, 1.0),
               std::invalid_argument);
  EXPECT_THROW(gauss_newton_uncertainty(Eigen::Vector2d(1, 1), Eigen::VectorXd::Ones(5), j, 0.95, {"a"}),
               std::invalid_argument);
}

TEST(FiniteDifferenceSteps, NominalReducedAndOneSided) {
  const double eps = std::numeric_limits<double>::epsilon();
  const Eigen::Vector4d x(2.0, -0.5, 1.0 - 1e-7, 0.0);
  const Eigen::Vector4d lower(-10.0, -10.0, 0.0, 0.0), upper(10.0, 10.0, 1.0, 1.0), typical(1.0, 1.0, 1.0, 1e-3);
  const std::vector<DifferenceStep> s = finite_difference_steps(x, lower, upper, typical);
  EXPECT_DOUBLE_EQ(s[0].step, std::cbrt(eps) * 2.0);  // |x| dominates
  EXPECT_DOUBLE_EQ(s[1].step, std::cbrt(eps) * 1.0);  // typical dominates
  EXPECT_EQ(s[1].scheme, DifferenceScheme::central);
  EXPECT_EQ(s[2].scheme, DifferenceScheme::central);  // 1e-7 of room: central, reduced to fit
  EXPECT_LE(x[2] + s[2].step, upper[2]);
  EXPECT_LT(s[2].step, std::cbrt(eps));
  EXPECT_EQ(s[3].scheme, DifferenceScheme::one_sided);  // on the lower bound: forward
  EXPECT_DOUBLE_EQ(s[3].step, std::sqrt(eps) * 1e-3);
  const Eigen::VectorXd h = central_difference_steps(x, lower, upper, typical);
  for (Eigen::Index j = 0; j < 4; ++j) EXPECT_EQ(h[j], s[static_cast<std::size_t>(j)].step);
  // On the upper bound the one-sided step points down.
  const std::vector<DifferenceStep> top =
      finite_difference_steps(Eigen::VectorXd::Constant(1, 1.0), lower.segment(2, 1), upper.segment(2, 1),
                              typical.segment(2, 1));
  EXPECT_EQ(top[0].scheme, DifferenceScheme::one_sided);
  EXPECT_LT(top[0].step, 0.0);
  EXPECT_THROW(finite_difference_steps(Eigen::VectorXd::Constant(1, 2.0), lower.segment(2, 1), upper.segment(2, 1),
                                       typical.segment(2, 1)),
               std::invalid_argument);
}

TEST(FiniteDifferenceSteps, DerivativesOfExpAreAccurate) {
  // d/dx exp(x) = exp(x), at interior points, next to a bound and on bounds.
  const Eigen::VectorXd x = (Eigen::VectorXd(5) << 0.7, -3.0, 1.0 - 1e-7, 0.0, 1.0).finished();
  const Eigen::VectorXd lower = Eigen::VectorXd::Constant(5, 0.0).cwiseMin(x);
  const Eigen::VectorXd upper = Eigen::VectorXd::Constant(5, 1.0).cwiseMax(x);
  const std::vector<DifferenceStep> steps = finite_difference_steps(x, lower, upper, Eigen::VectorXd::Ones(5));
  for (Eigen::Index j = 0; j < 5; ++j) {
    const DifferenceStep s = steps[static_cast<std::size_t>(j)];
    const double xj = x[j];
    const double derivative = s.scheme == DifferenceScheme::central
                                  ? (std::exp(xj + s.step) - std::exp(xj - s.step)) / (2.0 * s.step)
                                  : (std::exp(xj + s.step) - std::exp(xj)) / s.step;
    const double tolerance = s.scheme == DifferenceScheme::central ? 1e-8 : 1e-7;
    EXPECT_NEAR(derivative / std::exp(xj), 1.0, tolerance) << "x = " << xj;
    EXPECT_GE(xj + s.step, lower[j]);
    EXPECT_LE(xj + s.step, upper[j]);
    if (s.scheme == DifferenceScheme::central) {
      EXPECT_GE(xj - s.step, lower[j]);
    }
  }
}

TEST(ProfileLikelihoodInterval, QuadraticProfileGivesTheWaldInterval) {
  // rss = 7 + s^2 ((v - 0.3) / se)^2: deviance ((v - 0.3) / se)^2, so the
  // interval is 0.3 -+ sqrt(chi2_1(0.95)) se = 0.3 -+ 1.959964 se.
  const double s2 = 0.01, se = 0.05, centre = 0.3;
  std::vector<double> values, rss;
  for (int i = 0; i <= 400; ++i) {
    values.push_back(0.0512 + 0.5 * i / 400.0);  // the grid misses the centre
    rss.push_back(7.0 + s2 * std::pow((values.back() - centre) / se, 2));
  }
  const ProfileInterval p = profile_likelihood_interval(values, rss, s2);
  EXPECT_NEAR(p.best, centre, 1e-12);
  EXPECT_NEAR(p.lower, centre - 1.959963984540054 * se, 1e-4 * se);
  EXPECT_NEAR(p.upper, centre + 1.959963984540054 * se, 1e-4 * se);
  EXPECT_FALSE(p.lower_open);
  EXPECT_FALSE(p.upper_open);
  EXPECT_TRUE(p.identifiable);
  // chi2_1(0.682689492) = 1: one standard error.
  const ProfileInterval one_sigma = profile_likelihood_interval(values, rss, s2, 0.6826894921370859);
  EXPECT_NEAR(one_sigma.upper - centre, se, 1e-4 * se);
}

TEST(ProfileLikelihoodInterval, FlatProfileIsNotIdentifiable) {
  std::vector<double> values, rss;
  for (int i = 0; i < 50; ++i) {
    values.push_back(0.1 * i);
    rss.push_back(3.0 + 1e-3 * std::sin(i));  // wiggles far below the threshold of 3.84 s^2
  }
  const ProfileInterval p = profile_likelihood_interval(values, rss, 0.01);
  EXPECT_FALSE(p.identifiable);
  EXPECT_TRUE(p.lower_open);
  EXPECT_TRUE(p.upper_open);
  EXPECT_EQ(p.lower, -kInf);
  EXPECT_EQ(p.upper, kInf);
}

TEST(ProfileLikelihoodInterval, OneSidedRiseGivesAnOpenEnd) {
  // Deviance exp(v) - exp(-8) on [-8, 3]: the minimum is on the lower edge, the
  // upper end is where exp(v) = chi2_1(0.95) + exp(-8).
  const double s2 = 0.04;
  std::vector<double> values, rss;
  for (int i = 0; i <= 1100; ++i) {
    values.push_back(-8.0 + 0.01 * i);
    rss.push_back(5.0 + s2 * std::exp(values.back()));
  }
  const ProfileInterval p = profile_likelihood_interval(values, rss, s2);
  EXPECT_TRUE(p.identifiable);
  EXPECT_TRUE(p.lower_open);
  EXPECT_EQ(p.lower, -kInf);
  EXPECT_FALSE(p.upper_open);
  EXPECT_DOUBLE_EQ(p.best, -8.0);
  EXPECT_NEAR(p.upper, std::log(3.841458820694124 + std::exp(-8.0)), 1e-4);
}

TEST(ProfileLikelihoodInterval, RejectsBadGrids) {
  EXPECT_THROW(profile_likelihood_interval({0.0, 2.0, 1.0}, {1.0, 1.0, 1.0}, 1.0), std::invalid_argument);
  EXPECT_THROW(profile_likelihood_interval({0.0, 1.0}, {1.0}, 1.0), std::invalid_argument);
  EXPECT_THROW(profile_likelihood_interval({0.0, 1.0}, {1.0, 2.0}, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace rover::study
