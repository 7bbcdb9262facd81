// Tests of study/estimators/replicate_error: prefix moments against closed forms, the
// replicate RMS error and spread on hand-computed cases, the power-law fit and
// the runs for a target error on exact power laws, and the whole measurement
// on synthetic data with known answers: i.i.d. normal draws (RMS error of the
// mean sigma / sqrt(N), of the sd sigma sqrt(2 (1 - c4(N))) ~ sigma / sqrt(2N))
// and a smooth integrand on Monte Carlo and Owen-scrambled Sobol' designs
// (slopes -1/2 and steeper; Owen 1997).
#include "study/estimators/replicate_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "study/design/design.hpp"

namespace rover::study {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// c4(n) = E[s] / sigma for n normal draws (s with n - 1).
double c4(int n) {
  return std::sqrt(2.0 / (n - 1)) * std::exp(std::lgamma(0.5 * n) - std::lgamma(0.5 * (n - 1)));
}

std::vector<double> as_doubles(const std::vector<int>& sizes) { return {sizes.begin(), sizes.end()}; }

TEST(ReplicateError, PrefixMomentsOfOneToNFollowTheClosedForm) {
  // 1, 2, ..., n: mean (n + 1) / 2, variance n (n + 1) / 12; the tail (NaN) is not read.
  std::vector<double> values;
  for (int i = 1; i <= 100; ++i) values.push_back(i);
  values.push_back(kNaN);
  for (int n : {2, 7, 64, 100}) {
    const SampleMoments m = prefix_moments(values, n);
    EXPECT_DOUBLE_EQ(m.mean, 0.5 * (n + 1)) << n;
    EXPECT_NEAR(m.sd, std::sqrt(n * (n + 1) / 12.0), 1e-12 * n) << n;
  }
  EXPECT_THROW(prefix_moments(values, 1), std::invalid_argument);
  EXPECT_THROW(prefix_moments(values, 102), std::invalid_argument);
  EXPECT_THROW(prefix_moments(values, 101), std::invalid_argument);  // the NaN is in the prefix
}

TEST(ReplicateError, PrefixCurveMomentsOfAnAffineFamilyFollowTheClosedForm) {
  // curve_i(t) = a(t) + b(t) z_i with z_i = i + 1: mean a + b (n + 1) / 2, sd |b| sqrt(n (n + 1) / 12).
  const int rows = 40, times = 5, n = 32;
  const Eigen::VectorXd a = Eigen::VectorXd::LinSpaced(times, 0.2, 0.3);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(times, -2e-3, 2e-3);  // b = 0 at the middle sample
  Eigen::MatrixXd curves(rows, times);
  for (int i = 0; i < rows; ++i) curves.row(i) = (a + b * (i + 1)).transpose();
  curves.bottomRows(rows - n).setConstant(kNaN);  // failed runs after the prefix are not read
  const CurveMoments m = prefix_curve_moments(curves, n);
  ASSERT_EQ(m.mean.size(), times);
  ASSERT_EQ(m.sd.size(), times);
  for (int t = 0; t < times; ++t) {
    EXPECT_NEAR(m.mean(t), a(t) + b(t) * 0.5 * (n + 1), 1e-15) << t;
    EXPECT_NEAR(m.sd(t), std::abs(b(t)) * std::sqrt(n * (n + 1) / 12.0), 1e-15) << t;
  }
  EXPECT_EQ(m.sd(2), 0.0);
  EXPECT_THROW(prefix_curve_moments(curves, n + 1), std::invalid_argument);
  EXPECT_THROW(prefix_curve_moments(curves, rows + 1), std::invalid_argument);
  EXPECT_THROW(prefix_curve_moments(curves, 1), std::invalid_argument);
}

TEST(ReplicateError, PowerOfTwoSizesLieInTheRange) {
  EXPECT_EQ(power_of_two_sizes(4, 64), (std::vector<int>{4, 8, 16, 32, 64}));
  EXPECT_EQ(power_of_two_sizes(3, 100), (std::vector<int>{4, 8, 16, 32, 64}));
  EXPECT_EQ(power_of_two_sizes(1, 1), (std::vector<int>{1}));
  EXPECT_EQ(power_of_two_sizes(1 << 30, std::numeric_limits<int>::max()), (std::vector<int>{1 << 30}));
  EXPECT_THROW(power_of_two_sizes(0, 8), std::invalid_argument);
  EXPECT_THROW(power_of_two_sizes(5, 7), std::invalid_argument);
}

TEST(ReplicateError, RmsErrorAndSpreadOfHandComputedReplicates) {
  // Scalars {1, 3} against 0: RMS sqrt((1 + 9) / 2) = sqrt(5); sd of {1, 3} = sqrt(2).
  const std::vector<double> scalars{1.0, 3.0};
  ReplicateError e = replicate_error(scalars, 0.0);
  EXPECT_DOUBLE_EQ(e.rms_error, std::sqrt(5.0));
  EXPECT_DOUBLE_EQ(e.spread, std::sqrt(2.0));
  // Against their mean, the RMS error is the spread with an R (not R - 1) denominator.
  e = replicate_error(scalars, 2.0);
  EXPECT_DOUBLE_EQ(e.rms_error, 1.0);

  // Curves: replicate r = reference + c_r (+ a zero-mean wiggle d_r(t)):
  // rms^2 = mean_r c_r^2 + mean_{r,t} d_r(t)^2, spread^2 = mean_t var_r(c_r + d_r(t)).
  const Eigen::VectorXd reference = Eigen::VectorXd::LinSpaced(4, 1.0, 4.0);
  const Eigen::Vector3d offsets(0.1, -0.2, 0.4);
  Eigen::MatrixXd estimates = (Eigen::VectorXd::Ones(3) * reference.transpose()).colwise() + offsets;
  e = replicate_error(estimates, reference);
  EXPECT_NEAR(e.rms_error, std::sqrt((0.01 + 0.04 + 0.16) / 3.0), 1e-15);
  const double mean_offset = offsets.mean();
  EXPECT_NEAR(e.spread, std::sqrt((offsets.array() - mean_offset).square().sum() / 2.0), 1e-15);
  estimates(0, 0) += 0.3;  // one sample of one replicate: adds 0.3^2 / (3 * 4) ... to the MSE
  const double mse = ((0.4 * 0.4) + 3 * 0.01 + 4 * 0.04 + 4 * 0.16) / 12.0;
  EXPECT_NEAR(replicate_error(estimates, reference).rms_error, std::sqrt(mse), 1e-15);

  EXPECT_THROW(replicate_error(std::vector<double>{1.0}, 0.0), std::invalid_argument);
  EXPECT_THROW(replicate_error(estimates, Eigen::VectorXd::Zero(3)), std::invalid_argument);
  EXPECT_THROW(replicate_error(std::vector<double>{1.0, kNaN}, 0.0), std::invalid_argument);
}

TEST(ReplicateError, AnExactPowerLawIsRecoveredWithItsRunsForATarget) {
  std::vector<int> sizes = power_of_two_sizes(4, 1024);
  std::vector<double> errors;
  for (int n : sizes) errors.push_back(3.0 * std::pow(n, -0.75));
  const PowerLawFit fit = fit_power_law(as_doubles(sizes), errors);
  EXPECT_NEAR(fit.exponent, -0.75, 1e-12);
  EXPECT_NEAR(fit.coefficient, 3.0, 1e-11);
  EXPECT_NEAR(fit.exponent_se, 0.0, 1e-12);
  EXPECT_EQ(fit.points, 9);
  EXPECT_DOUBLE_EQ(fit.n_min, 4.0);
  EXPECT_NEAR(fit.n_max, 1024.0, 1e-9);
  EXPECT_NEAR(fit.error_at(4096.0), 3.0 * std::pow(4096.0, -0.75), 1e-12);

  // Inside the measured range: found by the fit and observed at the same N.
  RunsForError runs = runs_for_error(fit, sizes, errors, 3.0 * std::pow(256.0, -0.75));
  EXPECT_NEAR(runs.fitted, 256.0, 1e-8);
  EXPECT_EQ(runs.observed, 256);
  EXPECT_FALSE(runs.extrapolated);
  // Ten times smaller: N grows by 10^(1 / 0.75), beyond the measurements.
  runs = runs_for_error(fit, sizes, errors, 0.1 * 3.0 * std::pow(256.0, -0.75));
  EXPECT_NEAR(runs.fitted, 256.0 * std::pow(10.0, 1.0 / 0.75), 1e-6);
  EXPECT_EQ(runs.observed, 0);
  EXPECT_TRUE(runs.extrapolated);

  // Noise on the log scale: the exponent's standard error covers the truth.
  std::vector<double> noisy = errors;
  for (std::size_t k = 0; k < noisy.size(); ++k) noisy[k] *= (k % 2 == 0) ? 1.1 : 1.0 / 1.1;
  const PowerLawFit noisy_fit = fit_power_law(as_doubles(sizes), noisy);
  EXPECT_GT(noisy_fit.exponent_se, 0.0);
  EXPECT_NEAR(noisy_fit.exponent, -0.75, 3.0 * noisy_fit.exponent_se);

  // Two points: an exact line, no standard error.
  const PowerLawFit two = fit_power_law(std::vector<double>{10.0, 1000.0}, std::vector<double>{1.0, 0.1});
  EXPECT_NEAR(two.exponent, -0.5, 1e-14);
  EXPECT_TRUE(std::isnan(two.exponent_se));

  EXPECT_THROW(fit_power_law(std::vector<double>{8.0}, std::vector<double>{1.0}), std::invalid_argument);
  EXPECT_THROW(fit_power_law(std::vector<double>{8.0, 8.0}, std::vector<double>{1.0, 0.5}), std::invalid_argument);
  EXPECT_THROW(fit_power_law(std::vector<double>{8.0, 16.0}, std::vector<double>{1.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(fit_power_law(std::vector<double>{8.0, 16.0}, std::vector<double>{1.0}), std::invalid_argument);
}

TEST(ReplicateError, ObservedRunsNeedTheErrorToStayBelowTheTarget) {
  const std::vector<int> sizes{1, 2, 4, 8};
  const std::vector<double> errors{0.5, 2.0, 0.5, 0.5};  // below the target at 1, above at 2
  const PowerLawFit fit = fit_power_law(as_doubles(sizes), errors);
  EXPECT_EQ(runs_for_error(fit, sizes, errors, 1.0).observed, 4);
  EXPECT_EQ(runs_for_error(fit, sizes, errors, 0.4).observed, 0);
  // An error growing with N never reaches a smaller target.
  const PowerLawFit growing = fit_power_law(std::vector<double>{1.0, 4.0}, std::vector<double>{1.0, 2.0});
  const RunsForError runs = runs_for_error(growing, std::vector<int>{1, 4}, std::vector<double>{1.0, 2.0}, 0.5);
  EXPECT_TRUE(std::isinf(runs.fitted));
  EXPECT_TRUE(runs.extrapolated);
  EXPECT_THROW(runs_for_error(fit, sizes, errors, 0.0), std::invalid_argument);
  EXPECT_THROW(runs_for_error(fit, std::vector<int>{1, 1, 4, 8}, errors, 1.0), std::invalid_argument);
}

// R replicates of N_max i.i.d. Normal(mu, sigma) draws; prefixes N = 8 .. 256.
// Known answers: RMS error of the mean sigma / sqrt(N); of the sd
// sqrt(E (s - sigma)^2) = sigma sqrt(2 (1 - c4(N))), ~ sigma / sqrt(2N).
TEST(ReplicateError, IidNormalDrawsGiveTheClosedFormErrorsAndSlopes) {
  const double mu = 0.168, sigma = 6e-4;
  const int replicates = 1000, n_max = 256;
  const std::vector<int> sizes = power_of_two_sizes(8, n_max);
  std::mt19937_64 engine(20260101);
  std::normal_distribution<double> normal(mu, sigma);
  Eigen::MatrixXd means(replicates, sizes.size()), sds(replicates, sizes.size());
  std::vector<double> draws(n_max);
  for (int r = 0; r < replicates; ++r) {
    for (double& x : draws) x = normal(engine);
    for (std::size_t k = 0; k < sizes.size(); ++k) {
      const SampleMoments m = prefix_moments(draws, sizes[k]);
      means(r, k) = m.mean;
      sds(r, k) = m.sd;
    }
  }
  // The relative sd of an RMS estimated from R replicates is about sqrt(1 / 2R)
  // (mean) to sqrt(1 / R) (sd): 2.2 % to 3.2 % here; allow 4 of them.
  std::vector<double> mean_errors, sd_errors;
  for (std::size_t k = 0; k < sizes.size(); ++k) {
    const int n = sizes[k];
    const ReplicateError mean_error = replicate_error(means.col(k), Eigen::VectorXd::Constant(1, mu));
    const ReplicateError sd_error = replicate_error(sds.col(k), Eigen::VectorXd::Constant(1, sigma));
    EXPECT_NEAR(mean_error.rms_error / (sigma / std::sqrt(n)), 1.0, 0.09) << n;
    EXPECT_NEAR(sd_error.rms_error / (sigma * std::sqrt(2.0 * (1.0 - c4(n)))), 1.0, 0.13) << n;
    // The mean is unbiased: its spread estimates the same error without the reference.
    EXPECT_NEAR(mean_error.spread / mean_error.rms_error, 1.0, 0.09) << n;
    mean_errors.push_back(mean_error.rms_error / sigma);
    sd_errors.push_back(sd_error.rms_error / sigma);
  }
  const PowerLawFit mean_fit = fit_power_law(as_doubles(sizes), mean_errors);
  const PowerLawFit sd_fit = fit_power_law(as_doubles(sizes), sd_errors);
  EXPECT_NEAR(mean_fit.exponent, -0.5, 0.04);
  EXPECT_NEAR(mean_fit.coefficient, 1.0, 0.15);
  EXPECT_NEAR(sd_fit.exponent, -0.5, 0.05);
  // 1 % relative error on the sd: sigma / sqrt(2N) = 0.01 sigma at N = 5000.
  const RunsForError runs = runs_for_error(sd_fit, sizes, sd_errors, 0.01);
  EXPECT_NEAR(runs.fitted / 5000.0, 1.0, 0.25);
  EXPECT_TRUE(runs.extrapolated);
  EXPECT_EQ(runs.observed, 0);
}

// f(u) = sum_j u_j^2 on [0, 1]^3: mean 1, sd sqrt(3 (1/5 - 1/9)) = sqrt(4/15).
// Monte Carlo prefixes converge as N^-1/2; the prefixes of an Owen-scrambled
// Sobol' sequence (a net at every power of two) converge much faster for
// this smooth integrand, for the sd as well as the mean.
TEST(ReplicateError, ScrambledSobolPrefixesConvergeFasterThanMonteCarlo) {
  const int replicates = 64, n_max = 1024, dimensions = 3;
  const double exact_mean = 1.0, exact_sd = std::sqrt(4.0 / 15.0);
  const std::vector<int> sizes = power_of_two_sizes(16, n_max);
  for (DesignType type : {DesignType::kMonteCarlo, DesignType::kSobol}) {
    Eigen::MatrixXd means(replicates, sizes.size()), sds(replicates, sizes.size());
    for (int r = 0; r < replicates; ++r) {
      const DesignMatrix u = unit_design(type, n_max, dimensions, 1000 + static_cast<std::uint64_t>(r));
      const Eigen::VectorXd f = u.array().square().rowwise().sum();
      for (std::size_t k = 0; k < sizes.size(); ++k) {
        const SampleMoments m = prefix_moments(std::span<const double>(f.data(), f.size()), sizes[k]);
        means(r, k) = m.mean;
        sds(r, k) = m.sd;
      }
    }
    std::vector<double> mean_errors, sd_errors;
    for (std::size_t k = 0; k < sizes.size(); ++k) {
      mean_errors.push_back(replicate_error(means.col(k), Eigen::VectorXd::Constant(1, exact_mean)).rms_error);
      sd_errors.push_back(replicate_error(sds.col(k), Eigen::VectorXd::Constant(1, exact_sd)).rms_error);
    }
    const PowerLawFit mean_fit = fit_power_law(as_doubles(sizes), mean_errors);
    const PowerLawFit sd_fit = fit_power_law(as_doubles(sizes), sd_errors);
    std::cout << "  " << design_type_name(type) << ": mean error ~ N^" << mean_fit.exponent
              << ", sd error ~ N^" << sd_fit.exponent << "\n";
    if (type == DesignType::kMonteCarlo) {
      EXPECT_NEAR(mean_fit.exponent, -0.5, 0.1);
      EXPECT_NEAR(sd_fit.exponent, -0.5, 0.1);
    } else {
      EXPECT_LT(mean_fit.exponent, -1.3);
      EXPECT_LT(sd_fit.exponent, -1.0);
    }
  }
}

}  // namespace
}  // namespace rover::study
