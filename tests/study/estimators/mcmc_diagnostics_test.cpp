// Chain diagnostics (study/estimators/mcmc_diagnostics.cpp) against series whose
// autocorrelation time is known in closed form.
#include "study/estimators/mcmc_diagnostics.hpp"

#include <cmath>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <gtest/gtest.h>

namespace rover::study {
namespace {

// steps x walkers stationary AR(1) series x_t = phi x_{t-1} + e_t, e_t ~ N(0, 1).
// Its integrated autocorrelation time is (1 + phi) / (1 - phi).
Eigen::MatrixXd ar1_chain(double phi, Eigen::Index steps, Eigen::Index walkers, std::uint64_t seed) {
  boost::random::mt19937_64 engine(seed);
  boost::random::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd chain(steps, walkers);
  for (Eigen::Index w = 0; w < walkers; ++w) {
    double x = normal(engine) / std::sqrt(1.0 - phi * phi);  // start in the stationary law
    for (Eigen::Index t = 0; t < steps; ++t) {
      x = phi * x + normal(engine);
      chain(t, w) = x;
    }
  }
  return chain;
}

TEST(IntegratedAutocorrelationTime, Ar1MatchesClosedForm) {
  const double phi = 0.9;  // tau = 19
  const Eigen::MatrixXd chain = ar1_chain(phi, 10000, 16, 7);
  const double tau = integrated_autocorrelation_time(chain);
  EXPECT_NEAR(tau, (1.0 + phi) / (1.0 - phi), 0.15 * 19.0);
  EXPECT_NEAR(effective_sample_size(chain), static_cast<double>(chain.size()) / tau, 1e-9);
}

TEST(IntegratedAutocorrelationTime, IndependentDrawsGiveOne) {
  const Eigen::MatrixXd chain = ar1_chain(0.0, 4000, 8, 3);
  EXPECT_NEAR(integrated_autocorrelation_time(chain), 1.0, 0.1);
  EXPECT_NEAR(effective_sample_size(chain), 32000.0, 3200.0);
}

TEST(IntegratedAutocorrelationTime, WalkersThatNeverMoveGiveNaN) {
  EXPECT_TRUE(std::isnan(integrated_autocorrelation_time(Eigen::MatrixXd::Constant(100, 4, 2.5))));
  EXPECT_THROW(integrated_autocorrelation_time(Eigen::MatrixXd::Zero(3, 4)), std::invalid_argument);
}

TEST(SplitRhat, HandComputedExample) {
  // Walker 0: 0 2 | 1 3, walker 1: 4 6 | 5 7. Half-chain means 1 2 5 6 (grand
  // mean 3.5), variances 2 each: W = 2, B = 2/3 * 17, var+ = W/2 + B/2 = 20/3,
  // R-hat = sqrt(10/3).
  Eigen::MatrixXd chain(4, 2);
  chain << 0, 4, 2, 6, 1, 5, 3, 7;
  EXPECT_NEAR(split_rhat(chain), std::sqrt(10.0 / 3.0), 1e-14);
  // An odd length drops the middle draw.
  Eigen::MatrixXd odd(5, 2);
  odd << 0, 4, 2, 6, 100, -100, 1, 5, 3, 7;
  EXPECT_NEAR(split_rhat(odd), std::sqrt(10.0 / 3.0), 1e-14);
}

TEST(SplitRhat, OneForIndependentWalkersAboveForTwoModes) {
  const Eigen::MatrixXd chain = ar1_chain(0.0, 2000, 16, 11);
  EXPECT_LT(std::abs(split_rhat(chain) - 1.0), 0.01);
  Eigen::MatrixXd two_modes = chain;
  two_modes.rightCols(8).array() += 5.0;  // half the walkers in another mode
  EXPECT_GT(split_rhat(two_modes), 1.1);
}

TEST(SplitRhat, CatchesATrendWithinEachWalker) {
  // Same drift in every walker: the full-chain means agree, only the split sees it.
  Eigen::MatrixXd chain = ar1_chain(0.0, 2000, 16, 13);
  for (Eigen::Index t = 0; t < chain.rows(); ++t) chain.row(t).array() += 4.0 * static_cast<double>(t) / 2000.0;
  EXPECT_GT(split_rhat(chain), 1.1);
}

TEST(DiagnoseChain, FlagsAChainShorterThanFiftyAutocorrelationTimes) {
  // tau = 19: 50 tau = 950 steps.
  const std::vector<Eigen::MatrixXd> short_run{ar1_chain(0.9, 500, 32, 17), ar1_chain(0.0, 500, 32, 19)};
  const ChainDiagnostics s = diagnose_chain(short_run, 8000, 0);
  EXPECT_TRUE(s.chain_too_short);
  EXPECT_NE(s.warning.find("too short"), std::string::npos);
  EXPECT_DOUBLE_EQ(s.acceptance_fraction, 8000.0 / (500.0 * 32.0));
  ASSERT_EQ(s.autocorrelation_time.size(), 2);
  EXPECT_GT(s.autocorrelation_time[0], 10.0 * s.autocorrelation_time[1]);

  const std::vector<Eigen::MatrixXd> long_run{ar1_chain(0.9, 3000, 32, 23), ar1_chain(0.0, 3000, 32, 29)};
  const ChainDiagnostics l = diagnose_chain(long_run, 48000, 0);
  EXPECT_FALSE(l.chain_too_short);
  EXPECT_TRUE(l.warning.empty()) << l.warning;
  EXPECT_DOUBLE_EQ(l.acceptance_fraction, 0.5);
  for (Eigen::Index q = 0; q < 2; ++q) {
    EXPECT_NEAR(l.effective_sample_size[q], 96000.0 / l.autocorrelation_time[q], 1e-6);
    EXPECT_LT(l.split_rhat[q], 1.01);
    EXPECT_LT(l.nested_rhat[q], 1.01);
  }
}

TEST(DiagnoseChain, DiscardedBurnInIsLeftOut) {
  Eigen::MatrixXd chain = ar1_chain(0.0, 1200, 16, 31);
  chain.topRows(200).array() += 50.0;  // walkers still far away during the first 200 steps
  const ChainDiagnostics with_burn_in = diagnose_chain({chain}, 0, 0);
  EXPECT_GT(with_burn_in.split_rhat[0], 1.1);
  EXPECT_GT(with_burn_in.nested_rhat[0], 1.1);
  EXPECT_NE(with_burn_in.warning.find("parameter 0: nested R-hat"), std::string::npos) << with_burn_in.warning;
  const ChainDiagnostics named = diagnose_chain({chain}, 0, 0, {"c_q"});
  EXPECT_NE(named.warning.find("c_q: nested R-hat"), std::string::npos) << named.warning;
  const ChainDiagnostics without = diagnose_chain({chain}, 0, 200);
  EXPECT_LT(without.split_rhat[0], 1.01);
  EXPECT_EQ(without.warning.find("R-hat"), std::string::npos) << without.warning;
  // A study's stricter bar is the one warned about.
  const double strict_bar = 1.0 + 0.5 * (without.nested_rhat[0] - 1.0);
  const ChainDiagnostics strict = diagnose_chain({chain}, 0, 200, {"c_q"}, strict_bar);
  EXPECT_NE(strict.warning.find("c_q: nested R-hat"), std::string::npos) << strict.warning;
  EXPECT_NE(strict.warning.find(">= max_rhat"), std::string::npos) << strict.warning;
  // Sokal's window on 1000 iid steps: tau ~ 1 (the data-dependent window biases it slightly low).
  EXPECT_NEAR(without.autocorrelation_time[0], 1.0, 0.15);
}

// Many short walkers: single walkers hold few independent draws, so their
// split R-hat stays above 1.01 on a stationary ensemble, while the nested
// R-hat of 4 superchains goes below it; walkers of one superchain stuck in
// another mode push it far above.
TEST(DiagnoseChain, NestedRhatJudgesManyShortWalkers) {
  const Eigen::MatrixXd stationary = ar1_chain(0.95, 1000, 64, 41);
  EXPECT_GT(split_rhat(stationary), 1.01);
  EXPECT_LT(nested_rhat(stationary, 4), 1.01);
  Eigen::MatrixXd stuck = stationary;
  stuck.leftCols(16).array() += 3.0;
  EXPECT_GT(nested_rhat(stuck, 4), 1.1);
  EXPECT_THROW(nested_rhat(stationary, 1), std::invalid_argument);
}

TEST(DiagnoseChain, RejectsInconsistentInput) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(100, 4), b = Eigen::MatrixXd::Random(99, 4);
  EXPECT_THROW(diagnose_chain({}, 0), std::invalid_argument);
  EXPECT_THROW(diagnose_chain({a, b}, 0), std::invalid_argument);
  EXPECT_THROW(diagnose_chain({a}, 0, 97), std::invalid_argument);
  EXPECT_THROW(diagnose_chain({a}, 401), std::invalid_argument);
}

}  // namespace
}  // namespace rover::study
