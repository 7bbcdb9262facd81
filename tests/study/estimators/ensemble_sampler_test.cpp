// Affine-invariant ensemble sampler (study/estimators/ensemble_sampler.cpp): sampled
// moments against closed-form Gaussian posteriors, reproducibility however the
// batch is evaluated and across a resume, and input checks.
#include "study/estimators/ensemble_sampler.hpp"

#include <cmath>
#include <iostream>
#include <limits>
#include <stdexcept>

#include <Eigen/LU>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <gtest/gtest.h>

#include "study/estimators/mcmc_diagnostics.hpp"

namespace rover::study {
namespace {

// log N(x; mean, precision^-1) up to a constant, for each row of `points`.
BatchLogDensity gaussian_log_density(const Eigen::VectorXd& mean, const Eigen::MatrixXd& precision) {
  return [mean, precision](const DesignMatrix& points) {
    Eigen::VectorXd values(points.rows());
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      const Eigen::VectorXd d = points.row(i).transpose() - mean;
      values[i] = -0.5 * d.dot(precision * d);
    }
    return values;
  };
}

DesignMatrix ball(Eigen::Index walkers, const Eigen::VectorXd& centre, double radius, std::uint64_t seed) {
  boost::random::mt19937_64 engine(seed);
  boost::random::normal_distribution<double> normal(0.0, radius);
  DesignMatrix points(walkers, centre.size());
  for (Eigen::Index w = 0; w < walkers; ++w)
    for (Eigen::Index q = 0; q < centre.size(); ++q) points(w, q) = centre[q] + normal(engine);
  return points;
}

bool bitwise_equal(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && (a.array() == b.array()).all();
}

// Sample mean and sd of one parameter's chain (steps x walkers) with their
// Monte Carlo standard errors from the effective sample sizes of x and of
// (x - mean)^2 (delta method for sd = sqrt(var)).
struct MomentEstimate {
  double mean, mean_error, sd, sd_error;
};
MomentEstimate moments(const Eigen::MatrixXd& chain) {
  const double n = static_cast<double>(chain.size());
  MomentEstimate m{};
  m.mean = chain.mean();
  const Eigen::MatrixXd squared = (chain.array() - m.mean).square().matrix();
  const double variance = squared.sum() / (n - 1.0);
  m.sd = std::sqrt(variance);
  m.mean_error = m.sd / std::sqrt(effective_sample_size(chain));
  const double fourth_central = squared.array().square().mean();
  const double variance_error = std::sqrt((fourth_central - variance * variance) / effective_sample_size(squared));
  m.sd_error = variance_error / (2.0 * m.sd);
  return m;
}

TEST(EnsembleSampler, CorrelatedGaussianMomentsMatch) {
  Eigen::Vector2d mean(1.0, -2.0);
  Eigen::Matrix2d covariance;
  covariance << 1.0, 0.8 * 1.0 * 2.0, 0.8 * 1.0 * 2.0, 4.0;
  const BatchLogDensity log_density = gaussian_log_density(mean, covariance.inverse());
  const EnsembleOptions options{32, 2.0, 42};
  const EnsembleState start = initial_ensemble_state(ball(32, Eigen::Vector2d::Zero(), 0.1, 1), log_density);
  const EnsembleChain burn_in = run_ensemble(start, log_density, options, 500);
  const EnsembleChain chain = run_ensemble(burn_in.final_state, log_density, options, 4000);

  const double acceptance = static_cast<double>(chain.accepted_moves) / (4000.0 * 32.0);
  std::cout << "2-D Gaussian: acceptance " << acceptance << ", tau "
            << integrated_autocorrelation_time(chain.samples[0]) << ", "
            << integrated_autocorrelation_time(chain.samples[1]) << "\n";
  EXPECT_GT(acceptance, 0.2);
  EXPECT_LT(acceptance, 0.8);
  for (Eigen::Index q = 0; q < 2; ++q) {
    const MomentEstimate m = moments(chain.samples[static_cast<std::size_t>(q)]);
    EXPECT_NEAR(m.mean, mean[q], 4.0 * m.mean_error) << "parameter " << q;
    EXPECT_NEAR(m.sd, std::sqrt(covariance(q, q)), 4.0 * m.sd_error) << "parameter " << q;
  }
  const Eigen::ArrayXXd x = chain.samples[0].array() - chain.samples[0].mean();
  const Eigen::ArrayXXd y = chain.samples[1].array() - chain.samples[1].mean();
  const double correlation = (x * y).sum() / std::sqrt(x.square().sum() * y.square().sum());
  EXPECT_NEAR(correlation, 0.8, 0.03);  // Monte Carlo error (1 - 0.8^2) / sqrt(ESS) ~ 0.006
}

TEST(EnsembleSampler, LinearGaussianRegressionPosteriorMatchesClosedForm) {
  // y = b0 + b1 t + b2 t^2 + noise (sd 0.3, known), prior b ~ N(m0, I).
  // Posterior: S = (I + X^T X / sigma^2)^-1, m = S (m0 + X^T y / sigma^2).
  const int n = 15;
  const double noise_sd = 0.3;
  Eigen::MatrixXd design(n, 3);
  Eigen::VectorXd y(n);
  boost::random::mt19937_64 engine(5);
  boost::random::normal_distribution<double> noise(0.0, noise_sd);
  for (int i = 0; i < n; ++i) {
    const double t = i / (n - 1.0);
    design.row(i) << 1.0, t, t * t;
    y[i] = 1.0 - 2.0 * t + 1.5 * t * t + noise(engine);
  }
  const Eigen::Vector3d prior_mean(0.5, 0.0, 0.0);
  const Eigen::MatrixXd posterior_precision =
      Eigen::MatrixXd::Identity(3, 3) + design.transpose() * design / (noise_sd * noise_sd);
  const Eigen::MatrixXd posterior_covariance = posterior_precision.inverse();
  const Eigen::VectorXd posterior_mean =
      posterior_covariance * (prior_mean + design.transpose() * y / (noise_sd * noise_sd));

  const BatchLogDensity log_density = [&](const DesignMatrix& points) {
    Eigen::VectorXd values(points.rows());
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      const Eigen::VectorXd b = points.row(i).transpose();
      values[i] = -0.5 * (y - design * b).squaredNorm() / (noise_sd * noise_sd) -
                  0.5 * (b - prior_mean).squaredNorm();
    }
    return values;
  };
  const EnsembleOptions options{16, 2.0, 9};
  const EnsembleState start = initial_ensemble_state(ball(16, prior_mean, 0.1, 2), log_density);
  const EnsembleChain burn_in = run_ensemble(start, log_density, options, 1000);
  const EnsembleChain chain = run_ensemble(burn_in.final_state, log_density, options, 6000);

  const ChainDiagnostics diagnostics = diagnose_chain(chain.samples, chain.accepted_moves);
  std::cout << "regression: acceptance " << diagnostics.acceptance_fraction << ", tau "
            << diagnostics.autocorrelation_time.transpose() << "\n";
  EXPECT_GT(diagnostics.acceptance_fraction, 0.2);
  EXPECT_LT(diagnostics.acceptance_fraction, 0.8);
  EXPECT_FALSE(diagnostics.chain_too_short) << diagnostics.warning;
  for (Eigen::Index q = 0; q < 3; ++q) {
    const MomentEstimate m = moments(chain.samples[static_cast<std::size_t>(q)]);
    EXPECT_NEAR(m.mean, posterior_mean[q], 4.0 * m.mean_error) << "parameter " << q;
    EXPECT_NEAR(m.sd, std::sqrt(posterior_covariance(q, q)), 4.0 * m.sd_error) << "parameter " << q;
  }
}

TEST(EnsembleSampler, ProposalsOutsideTheSupportAreNeverAccepted) {
  // Uniform on the unit square; NaN left of it, -inf elsewhere outside.
  const BatchLogDensity log_density = [](const DesignMatrix& points) {
    Eigen::VectorXd values(points.rows());
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      const double x = points(i, 0), y = points(i, 1);
      values[i] = x < 0.0 ? std::numeric_limits<double>::quiet_NaN()
                  : (x > 1.0 || y < 0.0 || y > 1.0) ? -std::numeric_limits<double>::infinity()
                                                    : 0.0;
    }
    return values;
  };
  const EnsembleOptions options{8, 2.0, 3};
  const EnsembleChain chain = run_ensemble(
      initial_ensemble_state(ball(8, Eigen::Vector2d(0.5, 0.5), 0.05, 4), log_density), log_density, options, 3000);
  for (const Eigen::MatrixXd& samples : chain.samples) {
    EXPECT_GE(samples.minCoeff(), 0.0);
    EXPECT_LE(samples.maxCoeff(), 1.0);
    EXPECT_NEAR(samples.bottomRows(2500).mean(), 0.5, 0.03);
  }
  EXPECT_TRUE(chain.log_density.allFinite());
}

TEST(EnsembleSampler, ChainDoesNotDependOnHowTheBatchIsEvaluated) {
  Eigen::Matrix3d precision;
  precision << 2.0, 0.5, 0.0, 0.5, 1.0, -0.3, 0.0, -0.3, 0.5;
  const BatchLogDensity in_order = gaussian_log_density(Eigen::Vector3d(1, 2, 3), precision);
  // The rows evaluated last to first, and in pieces of at most 3 rows.
  const BatchLogDensity reversed = [&](const DesignMatrix& points) {
    Eigen::VectorXd values(points.rows());
    for (Eigen::Index i = points.rows() - 1; i >= 0; --i) values[i] = in_order(points.row(i))[0];
    return values;
  };
  const BatchLogDensity in_pieces = [&](const DesignMatrix& points) {
    Eigen::VectorXd values(points.rows());
    for (Eigen::Index first = 0; first < points.rows(); first += 3) {
      const Eigen::Index count = std::min<Eigen::Index>(3, points.rows() - first);
      values.segment(first, count) = in_order(points.middleRows(first, count));
    }
    return values;
  };
  const EnsembleOptions options{10, 2.0, 77};
  const EnsembleState start = initial_ensemble_state(ball(10, Eigen::Vector3d::Zero(), 1.0, 8), in_order);
  const EnsembleChain a = run_ensemble(start, in_order, options, 200);
  const EnsembleChain b = run_ensemble(start, reversed, options, 200);
  const EnsembleChain c = run_ensemble(start, in_pieces, options, 200);
  EXPECT_GT(a.accepted_moves, 0);
  for (std::size_t q = 0; q < 3; ++q) {
    EXPECT_TRUE(bitwise_equal(a.samples[q], b.samples[q]));
    EXPECT_TRUE(bitwise_equal(a.samples[q], c.samples[q]));
  }
  EXPECT_EQ(a.accepted_moves, c.accepted_moves);
  // The seed matters (the equalities above are not vacuous).
  const EnsembleChain other_seed = run_ensemble(start, in_order, EnsembleOptions{10, 2.0, 78}, 200);
  EXPECT_FALSE(bitwise_equal(a.samples[0], other_seed.samples[0]));
}

TEST(EnsembleSampler, ResumedRunEqualsUninterruptedRun) {
  const BatchLogDensity log_density = gaussian_log_density(Eigen::Vector2d(0, 0), Eigen::Matrix2d::Identity());
  const EnsembleOptions options{6, 2.5, 123};
  const EnsembleState start = initial_ensemble_state(ball(6, Eigen::Vector2d(3, 3), 0.5, 6), log_density);
  const EnsembleChain whole = run_ensemble(start, log_density, options, 60);

  const EnsembleChain first = run_ensemble(start, log_density, options, 30);
  // Saved to flat arrays of doubles and read back, as a checkpoint would.
  const std::vector<double> saved_positions(first.final_state.positions.data(),
                                            first.final_state.positions.data() + first.final_state.positions.size());
  const std::vector<double> saved_log_density(first.final_state.log_density.begin(),
                                              first.final_state.log_density.end());
  EnsembleState restored;
  restored.positions = Eigen::Map<const DesignMatrix>(saved_positions.data(), 6, 2);
  restored.log_density = Eigen::Map<const Eigen::VectorXd>(saved_log_density.data(), 6);
  restored.step = first.final_state.step;
  const EnsembleChain second = run_ensemble(restored, log_density, options, 30);

  EXPECT_EQ(second.final_state.step, 60);
  EXPECT_TRUE(bitwise_equal(second.final_state.positions, whole.final_state.positions));
  EXPECT_TRUE(bitwise_equal(second.final_state.log_density, whole.final_state.log_density));
  for (std::size_t q = 0; q < 2; ++q)
    EXPECT_TRUE(bitwise_equal(second.samples[q], whole.samples[q].bottomRows(30)));
  EXPECT_EQ(first.accepted_moves + second.accepted_moves, whole.accepted_moves);
}

TEST(EnsembleSampler, MoveIsAffineInvariant) {
  // Sampling pi(A x + b) from A x0 + b gives A x + b of the chain sampling pi(x)
  // from x0 (Goodman & Weare 2010, section 2): same seed, same decisions.
  Eigen::Matrix2d a;
  a << 3.0, 0.0, 1.0, 0.01;
  const Eigen::Vector2d shift(-5.0, 100.0);
  const BatchLogDensity plain = gaussian_log_density(Eigen::Vector2d(0, 0), Eigen::Matrix2d::Identity());
  const BatchLogDensity mapped = [&](const DesignMatrix& points) {
    // y = A x + b, so x = A^-1 (y - b).
    DesignMatrix x = ((points.rowwise() - shift.transpose()) * a.inverse().transpose());
    return plain(x);
  };
  const EnsembleOptions options{8, 2.0, 5};
  const DesignMatrix x0 = ball(8, Eigen::Vector2d(1, 1), 1.0, 10);
  const DesignMatrix y0 = (x0 * a.transpose()).rowwise() + shift.transpose();
  const EnsembleChain x = run_ensemble(initial_ensemble_state(x0, plain), plain, options, 100);
  const EnsembleChain y = run_ensemble(initial_ensemble_state(y0, mapped), mapped, options, 100);
  EXPECT_EQ(x.accepted_moves, y.accepted_moves);
  const DesignMatrix x_mapped = (x.final_state.positions * a.transpose()).rowwise() + shift.transpose();
  EXPECT_LT((x_mapped - y.final_state.positions).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(EnsembleSampler, RejectsBadEnsembles) {
  const BatchLogDensity log_density = gaussian_log_density(Eigen::Vector2d(0, 0), Eigen::Matrix2d::Identity());
  const EnsembleState four = initial_ensemble_state(ball(4, Eigen::Vector2d::Zero(), 1.0, 1), log_density);
  EXPECT_NO_THROW(ensemble_step(four, log_density, EnsembleOptions{4, 2.0, 1}));
  const EnsembleState seven = initial_ensemble_state(ball(7, Eigen::Vector2d::Zero(), 1.0, 1), log_density);
  EXPECT_THROW(ensemble_step(seven, log_density, EnsembleOptions{7, 2.0, 1}), std::invalid_argument);  // odd
  const EnsembleState two = initial_ensemble_state(ball(2, Eigen::Vector2d::Zero(), 1.0, 1), log_density);
  EXPECT_THROW(ensemble_step(two, log_density, EnsembleOptions{2, 2.0, 1}), std::invalid_argument);  // < 2p
  EXPECT_THROW(ensemble_step(four, log_density, EnsembleOptions{6, 2.0, 1}), std::invalid_argument);
  EXPECT_THROW(ensemble_step(four, log_density, EnsembleOptions{4, 1.0, 1}), std::invalid_argument);
  const BatchLogDensity short_answer = [](const DesignMatrix&) { return Eigen::VectorXd::Zero(1).eval(); };
  EXPECT_THROW(ensemble_step(four, short_answer, EnsembleOptions{4, 2.0, 1}), std::runtime_error);
}

TEST(EnsembleSampler, InitialStateNamesTheWalkerOutsideTheSupport) {
  const BatchLogDensity log_density = [](const DesignMatrix& points) {
    Eigen::VectorXd values = Eigen::VectorXd::Zero(points.rows());
    values[3] = -std::numeric_limits<double>::infinity();
    values[5] = std::numeric_limits<double>::quiet_NaN();
    return values;
  };
  try {
    initial_ensemble_state(DesignMatrix::Zero(8, 2), log_density);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("walker 3"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rover::study
