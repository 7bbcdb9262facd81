// Independence Metropolis-Hastings with a Student-t proposal
// (study/estimators/independence_sampler.cpp): the proposal's density against
// Boost.Math's Student-t, its draws' moments, sampled moments of Gaussian and
// bounded targets under a proposal that is deliberately off, reproducibility
// and resume, and input checks.
#include "study/estimators/independence_sampler.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/LU>
#include <boost/math/distributions/students_t.hpp>
#include <gtest/gtest.h>

#include "study/estimators/mcmc_diagnostics.hpp"

namespace rover::study {
namespace {

BatchLogDensity gaussian_log_density(const Eigen::VectorXd& mean, const Eigen::MatrixXd& covariance) {
  const Eigen::MatrixXd precision = covariance.inverse();
  return [mean, precision](const DesignMatrix& points) {
    Eigen::VectorXd values(points.rows());
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      const Eigen::VectorXd d = points.row(i).transpose() - mean;
      values[i] = -0.5 * d.dot(precision * d);
    }
    return values;
  };
}

struct Chains {
  std::vector<Eigen::MatrixXd> samples;  // per parameter: steps x chains
  long accepted = 0;
};
Chains run(const StudentTProposal& q, const BatchLogDensity& target, const IndependenceOptions& options, long steps) {
  const Eigen::Index p = q.mean.size();
  Chains out{std::vector<Eigen::MatrixXd>(static_cast<std::size_t>(p), Eigen::MatrixXd(steps, options.chains)), 0};
  EnsembleState state = initial_independence_state(q, target, options);
  std::vector<bool> accepted;
  for (long s = 0; s < steps; ++s) {
    state = independence_step(state, q, target, options, &accepted);
    for (Eigen::Index k = 0; k < p; ++k) out.samples[static_cast<std::size_t>(k)].row(s) = state.positions.col(k).transpose();
    for (bool a : accepted) out.accepted += a;
  }
  return out;
}

TEST(StudentTProposal, DensityMatchesBoostInOneDimension) {
  const StudentTProposal q{Eigen::VectorXd::Constant(1, 2.0), Eigen::MatrixXd::Constant(1, 1, 0.25), 4.0};
  const boost::math::students_t_distribution<double> t(4.0);
  for (double x : {-3.0, 0.0, 1.7, 2.0, 2.5, 9.0})
    EXPECT_NEAR(student_t_log_density(q, Eigen::VectorXd::Constant(1, x)),
                std::log(boost::math::pdf(t, (x - 2.0) / 0.5) / 0.5), 1e-12);
}

TEST(StudentTProposal, DrawsHaveTheDistributionsMoments) {
  Eigen::MatrixXd scale(2, 2);
  scale << 1.0, 0.6, 0.6, 2.0;
  const StudentTProposal q{Eigen::Vector2d(1.0, -3.0), scale, 6.0};
  const DesignMatrix draws = draw_student_t(q, 200000, 7, 0);
  const Eigen::RowVectorXd mean = draws.colwise().mean();
  const Eigen::MatrixXd centred = draws.rowwise() - mean;
  const Eigen::MatrixXd covariance = centred.transpose() * centred / static_cast<double>(draws.rows() - 1);
  const Eigen::MatrixXd expected = scale * 6.0 / 4.0;  // nu / (nu - 2)
  EXPECT_NEAR(mean[0], 1.0, 0.01);
  EXPECT_NEAR(mean[1], -3.0, 0.015);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) EXPECT_NEAR(covariance(i, j), expected(i, j), 0.05 * expected(i, i)) << i << j;
}

// A correlated Gaussian target sampled with a proposal centred 0.5 sd off and
// with the wrong correlation: the chains' moments are the target's.
TEST(IndependenceSampler, SamplesACorrelatedGaussianFromAnOffProposal) {
  Eigen::MatrixXd covariance(2, 2);
  covariance << 0.04, 0.03, 0.03, 0.09;
  const Eigen::Vector2d mean(0.3, 1.0);
  const StudentTProposal q{mean + Eigen::Vector2d(0.1, -0.15), Eigen::Vector2d(0.05, 0.08).asDiagonal(), 4.0};
  const Chains c = run(q, gaussian_log_density(mean, covariance), {.chains = 16, .seed = 3}, 1500);
  const ChainDiagnostics d = diagnose_chain(c.samples, c.accepted, 0);
  for (int k = 0; k < 2; ++k) {
    const Eigen::MatrixXd& x = c.samples[static_cast<std::size_t>(k)];
    const double sd = std::sqrt(covariance(k, k));
    const double error = sd / std::sqrt(d.effective_sample_size[k]);
    EXPECT_NEAR(x.mean(), mean[k], 4.0 * error) << k;
    EXPECT_NEAR(std::sqrt((x.array() - x.mean()).square().mean()), sd, 0.05 * sd) << k;
    EXPECT_LT(d.autocorrelation_time[k], 5.0) << k;  // a random walk needs tens of steps
    EXPECT_LT(d.nested_rhat[k], 1.01) << k;
  }
  const Eigen::MatrixXd& x = c.samples[0];
  const Eigen::MatrixXd& y = c.samples[1];
  const double cov_xy = ((x.array() - x.mean()) * (y.array() - y.mean())).mean();
  EXPECT_NEAR(cov_xy / std::sqrt(0.04 * 0.09), 0.5, 0.05);
  EXPECT_GT(d.acceptance_fraction, 0.4);
}

// A target with a bounded support (a half-normal on x > 0): no sample leaves
// it, and the mean is the half-normal's sqrt(2 / pi) sd.
TEST(IndependenceSampler, StaysInsideABoundedSupport) {
  const BatchLogDensity half_normal = [](const DesignMatrix& points) {
    Eigen::VectorXd values(points.rows());
    for (Eigen::Index i = 0; i < points.rows(); ++i)
      values[i] = points(i, 0) > 0.0 ? -0.5 * points(i, 0) * points(i, 0) : -std::numeric_limits<double>::infinity();
    return values;
  };
  const StudentTProposal q{Eigen::VectorXd::Constant(1, 0.5), Eigen::MatrixXd::Constant(1, 1, 0.6), 4.0};
  const Chains c = run(q, half_normal, {.chains = 8, .seed = 11}, 4000);
  EXPECT_GT(c.samples[0].minCoeff(), 0.0);
  EXPECT_NEAR(c.samples[0].mean(), std::sqrt(2.0 / M_PI), 0.03);
}

// A proposal far narrower than the target: the chains stick, and the
// diagnostics say so (the case a user must not miss).
TEST(IndependenceSampler, ATooNarrowProposalShowsInTheDiagnostics) {
  const StudentTProposal q{Eigen::VectorXd::Constant(1, 0.0), Eigen::MatrixXd::Constant(1, 1, 1e-4), 4.0};
  const Chains c = run(q, gaussian_log_density(Eigen::VectorXd::Constant(1, 0.0), Eigen::MatrixXd::Constant(1, 1, 1.0)),
                       {.chains = 8, .seed = 5}, 400);
  const ChainDiagnostics d = diagnose_chain(c.samples, c.accepted, 0);
  EXPECT_LT(d.effective_sample_size[0], 400.0);
}

TEST(IndependenceSampler, IsReproducibleAndResumesExactly) {
  const StudentTProposal q{Eigen::Vector2d(0.0, 0.0), Eigen::Matrix2d::Identity(), 4.0};
  const BatchLogDensity target = gaussian_log_density(Eigen::Vector2d(0.2, -0.1), Eigen::Matrix2d::Identity() * 0.8);
  const IndependenceOptions options{.chains = 4, .seed = 9};
  EnsembleState a = initial_independence_state(q, target, options);
  EnsembleState saved;
  for (int s = 0; s < 20; ++s) {
    a = independence_step(a, q, target, options);
    if (s == 9) saved = a;
  }
  EnsembleState b = saved;
  for (int s = 10; s < 20; ++s) b = independence_step(b, q, target, options);
  EXPECT_TRUE((a.positions.array() == b.positions.array()).all());
  EXPECT_TRUE((a.log_density.array() == b.log_density.array()).all());
  EXPECT_EQ(a.step, 20);
}

TEST(IndependenceSampler, RefusesBadInput) {
  const BatchLogDensity target = gaussian_log_density(Eigen::VectorXd::Zero(1), Eigen::MatrixXd::Identity(1, 1));
  const StudentTProposal singular{Eigen::VectorXd::Zero(2), Eigen::Matrix2d::Zero(), 4.0};
  EXPECT_THROW(draw_student_t(singular, 3, 1, 0), std::invalid_argument);
  const StudentTProposal q{Eigen::VectorXd::Zero(1), Eigen::MatrixXd::Identity(1, 1), 4.0};
  EXPECT_THROW(initial_independence_state(q, target, {.chains = 0}), std::invalid_argument);
  const BatchLogDensity nowhere = [](const DesignMatrix& points) {
    return Eigen::VectorXd::Constant(points.rows(), -std::numeric_limits<double>::infinity()).eval();
  };
  EXPECT_THROW(initial_independence_state(q, nowhere, {.chains = 2}), std::invalid_argument);
  const EnsembleState state = initial_independence_state(q, target, {.chains = 2});
  EXPECT_THROW(independence_step(state, q, target, {.chains = 3}), std::invalid_argument);
}

}  // namespace
}  // namespace rover::study
