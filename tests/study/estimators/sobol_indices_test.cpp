// Sobol' indices from pick-freeze designs (study/estimators/sobol_indices.cpp), checked on
// the analytic models of study/estimators/test_models.hpp: accuracy, convergence rate,
// bootstrap interval coverage, failed runs, second order and curves.
#include "study/estimators/sobol_indices.hpp"

#include <atomic>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/math/constants/constants.hpp>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/sobol.hpp>
#include <boost/random/uniform_01.hpp>
#include <gtest/gtest.h>

#include "study/estimators/test_models.hpp"
#include "study/estimators/work_stopped.hpp"

namespace rover::study {
namespace {

constexpr double kPi = boost::math::constants::pi<double>();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct BaseDesign {
  DesignMatrix A, B;  // N x d each, unit coordinates in (0, 1)
};

// Plain Monte Carlo: independent uniforms.
BaseDesign monte_carlo_base(int N, int d, std::uint64_t seed) {
  boost::random::mt19937_64 engine(seed);
  boost::random::uniform_01<double> uniform;
  BaseDesign base{DesignMatrix(N, d), DesignMatrix(N, d)};
  for (int g = 0; g < N; ++g) {
    for (int i = 0; i < d; ++i) base.A(g, i) = uniform(engine);
    for (int i = 0; i < d; ++i) base.B(g, i) = uniform(engine);
  }
  return base;
}

// Randomised quasi-Monte Carlo: the first N points of the 2d-dimensional
// Sobol' sequence, each coordinate XOR-ed with a random 64-bit word keyed by the
// seed (a random digital shift, which keeps the net property and makes the
// estimate unbiased over seeds). A: the first d coordinates, B: the last d.
BaseDesign sobol_base(int N, int d, std::uint64_t seed) {
  boost::random::sobol sequence(static_cast<unsigned>(2 * d));
  boost::random::mt19937_64 engine(seed);
  std::vector<std::uint64_t> shift(static_cast<std::size_t>(2 * d));
  for (auto& s : shift) s = engine();
  BaseDesign base{DesignMatrix(N, d), DesignMatrix(N, d)};
  for (int g = 0; g < N; ++g)
    for (int j = 0; j < 2 * d; ++j) {
      const std::uint64_t bits = static_cast<std::uint64_t>(sequence()) ^ shift[j];
      const double u = (static_cast<double>(bits >> 11) + 0.5) * 0x1p-53;  // in (0, 1)
      (j < d ? base.A(g, j) : base.B(g, j - d)) = u;
    }
  return base;
}

// Model outputs of a unit design, mapped to each model's inputs here.
Eigen::VectorXd ishigami_outputs(const DesignMatrix& unit) {
  Eigen::VectorXd y(unit.rows());
  for (Eigen::Index r = 0; r < unit.rows(); ++r) {
    double x[3];
    for (int i = 0; i < 3; ++i) x[i] = -kPi + 2.0 * kPi * unit(r, i);
    y[r] = ishigami(x);
  }
  return y;
}
Eigen::VectorXd sobol_g_outputs(const DesignMatrix& unit, const std::vector<double>& a) {
  Eigen::VectorXd y(unit.rows());
  for (Eigen::Index r = 0; r < unit.rows(); ++r) y[r] = sobol_g(unit.row(r).data(), a);
  return y;
}
DesignMatrix normal_inputs(const DesignMatrix& unit, const std::vector<double>& sds) {
  const boost::math::normal standard_normal;
  DesignMatrix x(unit.rows(), unit.cols());
  for (Eigen::Index r = 0; r < unit.rows(); ++r)
    for (Eigen::Index i = 0; i < unit.cols(); ++i)
      x(r, i) = sds[i] * boost::math::quantile(standard_normal, unit(r, i));
  return x;
}
Eigen::VectorXd linear_outputs(const DesignMatrix& unit, const std::vector<double>& coefficients,
                               const std::vector<double>& sds) {
  const DesignMatrix x = normal_inputs(unit, sds);
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index r = 0; r < x.rows(); ++r) y[r] = linear_model(x.row(r).data(), coefficients);
  return y;
}

enum class Model { kIshigami, kSobolG, kLinear };
const std::vector<double> kGA{0.0, 1.0, 4.5, 9.0, 99.0, 99.0, 99.0, 99.0};
const std::vector<double> kLinearCoefficients{1.0, -2.0, 0.5};
const std::vector<double> kLinearSds{1.0, 0.5, 3.0};

int dimensions(Model model) {
  return model == Model::kSobolG ? static_cast<int>(kGA.size()) : 3;
}
KnownIndices known(Model model) {
  switch (model) {
    case Model::kIshigami: return ishigami_indices();
    case Model::kSobolG: return sobol_g_indices(kGA);
    case Model::kLinear: return linear_indices(kLinearCoefficients, kLinearSds);
  }
  return {};
}
Eigen::VectorXd outputs(Model model, const DesignMatrix& unit) {
  switch (model) {
    case Model::kIshigami: return ishigami_outputs(unit);
    case Model::kSobolG: return sobol_g_outputs(unit, kGA);
    case Model::kLinear: return linear_outputs(unit, kLinearCoefficients, kLinearSds);
  }
  return {};
}
const char* name(Model model) {
  return model == Model::kIshigami ? "Ishigami" : model == Model::kSobolG ? "g-function" : "linear";
}
const char* name(SobolEstimator estimator) {
  return estimator == SobolEstimator::kSaltelliJansen ? "Saltelli-Jansen" : "Martinez";
}

SobolIndices run(Model model, const BaseDesign& base, const SobolOptions& options,
                 bool second_order = false) {
  const PickFreezeLayout layout{static_cast<int>(base.A.rows()), static_cast<int>(base.A.cols()),
                                second_order};
  return estimate_sobol_indices(layout, outputs(model, pick_freeze_design(base.A, base.B, second_order)),
                                options);
}

TEST(SobolIndices, PickFreezeDesignSwapsOneColumnPerRun) {
  const BaseDesign base = monte_carlo_base(3, 4, 7);
  for (bool second_order : {false, true}) {
    const PickFreezeLayout layout{3, 4, second_order};
    EXPECT_EQ(layout.runs_per_group(), second_order ? 10 : 6);
    EXPECT_EQ(layout.total_runs(), 3 * layout.runs_per_group());
    const DesignMatrix design = pick_freeze_design(base.A, base.B, second_order);
    ASSERT_EQ(design.rows(), layout.total_runs());
    for (int g = 0; g < 3; ++g) {
      const int first = g * layout.runs_per_group();
      EXPECT_EQ(design.row(first), base.A.row(g));
      EXPECT_EQ(design.row(first + 1), base.B.row(g));
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
          EXPECT_EQ(design(first + 2 + i, j), (i == j ? base.B : base.A)(g, j));
          if (second_order) {
            EXPECT_EQ(design(first + 6 + i, j), (i == j ? base.A : base.B)(g, j));
          }
        }
    }
  }
  EXPECT_THROW(pick_freeze_design(base.A, DesignMatrix(3, 2), false), std::invalid_argument);
}

// N = 4096 from a Sobol' base design: every exact index within 0.02 and within its 95 % interval.
TEST(SobolIndices, AnalyticModelsAreRecoveredWithinTheirIntervals) {
  for (Model model : {Model::kIshigami, Model::kSobolG, Model::kLinear})
    for (SobolEstimator estimator : {SobolEstimator::kSaltelliJansen, SobolEstimator::kMartinez}) {
      SCOPED_TRACE(std::string(name(model)) + ", " + name(estimator));
      SobolOptions options;
      options.estimator = estimator;
      const SobolIndices s = run(model, sobol_base(4096, dimensions(model), 11), options);
      const KnownIndices exact = known(model);
      EXPECT_EQ(s.groups_used, 4096);
      EXPECT_TRUE(s.dropped_groups.empty());
      EXPECT_EQ(s.S2.size(), 0);
      for (int i = 0; i < dimensions(model); ++i) {
        EXPECT_NEAR(s.S1[i], exact.S1[i], 0.02) << "S1 " << i;
        EXPECT_NEAR(s.ST[i], exact.ST[i], 0.02) << "ST " << i;
        EXPECT_LE(s.S1_lower[i], exact.S1[i]) << "S1 " << i;
        EXPECT_GE(s.S1_upper[i], exact.S1[i]) << "S1 " << i;
        EXPECT_LE(s.ST_lower[i], exact.ST[i]) << "ST " << i;
        EXPECT_GE(s.ST_upper[i], exact.ST[i]) << "ST " << i;
        EXPECT_LT(s.S1_upper[i] - s.S1_lower[i], 0.1) << "S1 " << i;
        EXPECT_LT(s.ST_upper[i] - s.ST_lower[i], 0.1) << "ST " << i;
      }
    }
}

TEST(SobolIndices, AnInputThatDoesNotEnterTheModelHasZeroIndicesAndAPointInterval) {
  // f = x0 + 0 x1 + 2 x2: swapping x1 changes no output, so f(A_B^1) = f(A) run by run.
  const std::vector<double> coefficients{1.0, 0.0, 2.0}, sds{1.0, 1.0, 1.0};
  const BaseDesign base = monte_carlo_base(256, 3, 9);
  const Eigen::VectorXd y = linear_outputs(pick_freeze_design(base.A, base.B, false), coefficients, sds);
  for (BootstrapInterval interval : {BootstrapInterval::kPercentile, BootstrapInterval::kBca}) {
    SobolOptions options;
    options.interval = interval;
    const SobolIndices s = estimate_sobol_indices({256, 3, false}, y, options);
    EXPECT_EQ(s.S1[1], 0.0);
    EXPECT_EQ(s.ST[1], 0.0);
    EXPECT_EQ(s.ST_lower[1], 0.0);
    EXPECT_EQ(s.ST_upper[1], 0.0);
    EXPECT_EQ(s.S1_lower[1], 0.0);
    EXPECT_EQ(s.S1_upper[1], 0.0);
    EXPECT_LT(s.ST_lower[2], s.ST[2]);  // the others have proper intervals
    EXPECT_GT(s.ST_upper[2], s.ST[2]);
  }
}

// A raised stop flag (a signal) ends the bootstrap with WorkStopped; without
// a bootstrap the flag is never read.
TEST(SobolIndices, AStopFlagEndsTheBootstrap) {
  const std::vector<double> coefficients{1.0, 0.5, 2.0}, sds{1.0, 1.0, 1.0};
  const BaseDesign base = monte_carlo_base(64, 3, 5);
  const Eigen::VectorXd y = linear_outputs(pick_freeze_design(base.A, base.B, false), coefficients, sds);
  std::atomic<bool> stop{true};
  SobolOptions options;
  options.stop = &stop;
  EXPECT_THROW(estimate_sobol_indices({64, 3, false}, y, options), WorkStopped);
  options.bootstrap_resamples = 0;
  EXPECT_TRUE(estimate_sobol_indices({64, 3, false}, y, options).S1.allFinite());
}

TEST(SobolIndices, MeanAndVarianceAreThoseOfTheOutput) {
  // Linear model: mean 0, variance sum c_i^2 s_i^2 = 1 + 1 + 2.25.
  SobolOptions options;
  options.bootstrap_resamples = 0;
  const SobolIndices s = run(Model::kLinear, sobol_base(4096, 3, 3), options);
  EXPECT_NEAR(s.mean, 0.0, 0.02);
  EXPECT_NEAR(s.variance, 4.25, 0.05);
  EXPECT_TRUE(std::isnan(s.S1_lower[0]) && std::isnan(s.ST_upper[2]));  // no bootstrap
}

// RMS error over seeds of all S1 and ST of the Ishigami function.
double rms_error(bool quasi_random, int N, int seeds) {
  const KnownIndices exact = ishigami_indices();
  SobolOptions options;
  options.bootstrap_resamples = 0;
  double sum2 = 0.0;
  for (int seed = 1; seed <= seeds; ++seed) {
    const auto s64 = static_cast<std::uint64_t>(seed);
    const BaseDesign base = quasi_random ? sobol_base(N, 3, s64) : monte_carlo_base(N, 3, s64);
    const SobolIndices s = run(Model::kIshigami, base, options);
    sum2 += (s.S1 - exact.S1).squaredNorm() + (s.ST - exact.ST).squaredNorm();
  }
  return std::sqrt(sum2 / (6.0 * seeds));
}

// Least-squares slope of log(rms) against log(N).
double log_log_slope(const std::vector<int>& Ns, const std::vector<double>& rms) {
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < Ns.size(); ++k) mx += std::log(Ns[k]), my += std::log(rms[k]);
  mx /= static_cast<double>(Ns.size());
  my /= static_cast<double>(Ns.size());
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < Ns.size(); ++k) {
    sxy += (std::log(Ns[k]) - mx) * (std::log(rms[k]) - my);
    sxx += (std::log(Ns[k]) - mx) * (std::log(Ns[k]) - mx);
  }
  return sxy / sxx;
}

TEST(SobolIndices, ErrorFallsLikeOneOverRootNAndFasterWithSobolPoints) {
  const std::vector<int> Ns{256, 512, 1024, 2048, 4096};
  const int seeds = 30;
  std::vector<double> mc, qmc;
  for (int N : Ns) {
    mc.push_back(rms_error(false, N, seeds));
    qmc.push_back(rms_error(true, N, seeds));
  }
  const double mc_slope = log_log_slope(Ns, mc), qmc_slope = log_log_slope(Ns, qmc);
  std::cout << "RMS error of the Ishigami S1, ST over " << seeds << " seeds:\n";
  for (std::size_t k = 0; k < Ns.size(); ++k)
    std::cout << "  N = " << Ns[k] << ": Monte Carlo " << mc[k] << ", Sobol' " << qmc[k] << "\n";
  std::cout << "  slopes: Monte Carlo " << mc_slope << ", Sobol' " << qmc_slope << "\n";
  EXPECT_NEAR(mc_slope, -0.5, 0.12);
  EXPECT_LT(qmc_slope, mc_slope - 0.15);
  for (std::size_t k = 0; k < Ns.size(); ++k) EXPECT_LT(qmc[k], mc[k]) << Ns[k];
  EXPECT_LT(qmc.back(), 0.5 * mc.back());
}

// Two-sided binomial acceptance region for the number of intervals that
// contain the truth out of n, at 95 % nominal coverage.
std::pair<int, int> binomial_region(int n, double level) {
  const boost::math::binomial binomial(n, 0.95);
  return {static_cast<int>(boost::math::quantile(binomial, 0.5 * level)),
          static_cast<int>(boost::math::quantile(boost::math::complement(binomial, 0.5 * level)))};
}

TEST(SobolIndices, IntervalsCoverTheTruthAtTheirNominalRate) {
  const int repeats = 200, N = 512, d = 3;
  const KnownIndices exact = known(Model::kLinear);
  // Each estimator with one of the two interval methods (both pairs would double the cost).
  for (const auto& [estimator, interval] :
       {std::pair{SobolEstimator::kSaltelliJansen, BootstrapInterval::kPercentile},
        std::pair{SobolEstimator::kMartinez, BootstrapInterval::kBca}}) {
    SobolOptions options;
    options.estimator = estimator;
    options.interval = interval;
    options.bootstrap_resamples = 500;
    std::vector<int> s1_hits(d, 0), st_hits(d, 0);
    for (int rep = 0; rep < repeats; ++rep) {
      options.seed = static_cast<std::uint64_t>(1000 + rep);
      const SobolIndices s =
          run(Model::kLinear, monte_carlo_base(N, d, static_cast<std::uint64_t>(rep + 1)), options);
      for (int i = 0; i < d; ++i) {
        s1_hits[i] += s.S1_lower[i] <= exact.S1[i] && exact.S1[i] <= s.S1_upper[i];
        st_hits[i] += s.ST_lower[i] <= exact.ST[i] && exact.ST[i] <= s.ST_upper[i];
      }
    }
    // Each count is Binomial(200, 0.95) if the intervals are honest; accept the
    // central 99.8 % (0.1 % per tail and per index).
    const auto [low, high] = binomial_region(repeats, 0.002);
    std::cout << name(estimator) << " coverage of 95 % "
              << (interval == BootstrapInterval::kBca ? "BCa" : "percentile") << " intervals over "
              << repeats
              << " repeats (accept " << low << ".." << high << "):";
    for (int i = 0; i < d; ++i) std::cout << " S1_" << i << " " << s1_hits[i];
    for (int i = 0; i < d; ++i) std::cout << " ST_" << i << " " << st_hits[i];
    std::cout << "\n";
    int total = 0;
    for (int i = 0; i < d; ++i) {
      EXPECT_GE(s1_hits[i], low) << name(estimator) << " S1 " << i;
      EXPECT_GE(st_hits[i], low) << name(estimator) << " ST " << i;
      EXPECT_LE(s1_hits[i], high) << name(estimator) << " S1 " << i;
      EXPECT_LE(st_hits[i], high) << name(estimator) << " ST " << i;
      total += s1_hits[i] + st_hits[i];
    }
    // Pooled over the six indices: the fraction is within 2.5 points of 0.95
    // (the intervals neither undercover nor are uselessly wide).
    EXPECT_NEAR(total / (2.0 * d * repeats), 0.95, 0.025) << name(estimator);
  }
}

TEST(SobolIndices, FailedRunsDropTheirGroupsAndNothingElse) {
  const int N = 256, d = 3;
  const BaseDesign base = monte_carlo_base(N, d, 5);
  const PickFreezeLayout layout{N, d, false};
  const int per_group = layout.runs_per_group();
  const Eigen::VectorXd clean = ishigami_outputs(pick_freeze_design(base.A, base.B, false));
  Eigen::VectorXd y = clean;
  y[3 * per_group + 0] = kNaN;                                        // A run of group 3
  y[17 * per_group + 4] = kNaN;                                       // a mixed run of group 17
  y[17 * per_group + 1] = std::numeric_limits<double>::infinity();   // and its B run
  y[200 * per_group + per_group - 1] = -std::numeric_limits<double>::infinity();
  const SobolOptions options;
  const SobolIndices s = estimate_sobol_indices(layout, y, options);
  EXPECT_EQ(s.dropped_groups, (std::vector<int>{3, 17, 200}));
  EXPECT_EQ(s.groups_used, N - 3);
  EXPECT_EQ(s.groups_total, N);

  // The same as a study that never had those groups.
  DesignMatrix A(N - 3, d), B(N - 3, d);
  for (int g = 0, kept = 0; g < N; ++g)
    if (g != 3 && g != 17 && g != 200) {
      A.row(kept) = base.A.row(g);
      B.row(kept++) = base.B.row(g);
    }
  const SobolIndices reference = estimate_sobol_indices(
      {N - 3, d, false}, ishigami_outputs(pick_freeze_design(A, B, false)), options);
  for (int i = 0; i < d; ++i) {
    EXPECT_NEAR(s.S1[i], reference.S1[i], 1e-12);
    EXPECT_NEAR(s.ST[i], reference.ST[i], 1e-12);
    EXPECT_NEAR(s.S1_lower[i], reference.S1_lower[i], 1e-12);
    EXPECT_NEAR(s.ST_upper[i], reference.ST_upper[i], 1e-12);
  }
  EXPECT_NEAR(s.mean, reference.mean, 1e-12);
  EXPECT_NEAR(s.variance, reference.variance, 1e-12);
  // Still close to the truth (N = 253, plain Monte Carlo).
  const KnownIndices exact = ishigami_indices();
  for (int i = 0; i < d; ++i) {
    EXPECT_NEAR(s.S1[i], exact.S1[i], 0.15);
    EXPECT_NEAR(s.ST[i], exact.ST[i], 0.15);
  }
}

TEST(SobolIndices, TooFewGroupsOrZeroVarianceThrowWithAReason) {
  const PickFreezeLayout layout{4, 2, false};
  Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(layout.total_runs(), 0.0, 1.0);
  y[0] = y[4] = y[9] = kNaN;  // groups 0, 1 (runs 0..3, 4..7) and 2 (runs 8..11)
  try {
    estimate_sobol_indices(layout, y, SobolOptions{});
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("only 1 of 4 groups"), std::string::npos) << e.what();
  }
  try {
    estimate_sobol_indices(layout, Eigen::VectorXd::Constant(layout.total_runs(), 0.1),
                           SobolOptions{});
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("variance is zero"), std::string::npos) << e.what();
  }
  EXPECT_THROW(estimate_sobol_indices(layout, Eigen::VectorXd::Zero(5), SobolOptions{}),
               std::invalid_argument);
}

// A bootstrap of a handful of groups (3 distinct resamples of 2 groups) gives
// intervals that look precise and cover nothing: below the minimum the bounds
// are NaN and the result says it has none.
TEST(SobolIndices, TooFewGroupsToResampleGiveNoIntervals) {
  for (const int groups : {2, kMinBootstrapSobolGroups - 1, kMinBootstrapSobolGroups}) {
    const SobolIndices s = run(Model::kIshigami, sobol_base(groups, 3, 5), SobolOptions{}, false);
    const bool expected = groups >= kMinBootstrapSobolGroups;
    EXPECT_EQ(s.has_intervals, expected) << groups << " groups";
    EXPECT_TRUE(s.S1.allFinite());
    EXPECT_EQ(s.S1_lower.allFinite() && s.ST_upper.allFinite(), expected) << groups << " groups";
    EXPECT_EQ(s.S1_lower.array().isNaN().all(), !expected) << groups << " groups";
  }
  SobolOptions none;
  none.bootstrap_resamples = 0;
  EXPECT_FALSE(run(Model::kIshigami, sobol_base(64, 3, 5), none, false).has_intervals);
}

TEST(SobolIndices, IshigamiSecondOrderIsTheX1X3Interaction) {
  const KnownIndices exact = ishigami_indices();
  for (SobolEstimator estimator : {SobolEstimator::kSaltelliJansen, SobolEstimator::kMartinez}) {
    SCOPED_TRACE(name(estimator));
    SobolOptions options;
    options.estimator = estimator;
    const SobolIndices s = run(Model::kIshigami, sobol_base(4096, 3, 21), options, true);
    ASSERT_EQ(s.S2.rows(), 3);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        if (j <= i) {
          EXPECT_TRUE(std::isnan(s.S2(i, j)) && std::isnan(s.S2_lower(i, j)));
          continue;
        }
        EXPECT_NEAR(s.S2(i, j), exact.S2(i, j), 0.03) << i << j;
        EXPECT_LE(s.S2_lower(i, j), exact.S2(i, j)) << i << j;
        EXPECT_GE(s.S2_upper(i, j), exact.S2(i, j)) << i << j;
      }
    // The first and total order are those of the first-order layout.
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(s.S1[i], exact.S1[i], 0.02);
      EXPECT_NEAR(s.ST[i], exact.ST[i], 0.02);
    }
  }
}

TEST(SobolIndices, CurvesGiveTheIndicesOfEachTimeAndTheirVarianceWeightedMean) {
  // y(t) = sum_i c_i(t) x_i, x_i ~ N(0, s_i); the last column is constant.
  const std::vector<double> sds{1.0, 2.0, 0.5};
  const std::vector<double> times{0.0, 0.25, 0.5, 0.75, 1.0};
  auto coefficients = [](double t) { return std::vector<double>{1.0, t, 2.0 * (1.0 - t)}; };
  const int N = 4096, d = 3, T = static_cast<int>(times.size()) + 1;
  const BaseDesign base = sobol_base(N, d, 4);
  const DesignMatrix unit = pick_freeze_design(base.A, base.B, false);
  const DesignMatrix x = normal_inputs(unit, sds);
  Eigen::MatrixXd Y(unit.rows(), T);
  for (Eigen::Index r = 0; r < Y.rows(); ++r) {
    for (int t = 0; t + 1 < T; ++t) Y(r, t) = linear_model(x.row(r).data(), coefficients(times[t]));
    Y(r, T - 1) = 2.5;
  }
  Y(7 * (d + 2) + 3, 1) = kNaN;  // one failed output of group 7
  const PickFreezeLayout layout{N, d, false};
  // The generalised index: sum_t V_i(t) / sum_t V(t).
  Eigen::VectorXd partial_sum = Eigen::VectorXd::Zero(d);
  double variance_sum = 0.0;
  for (double t : times) {
    const KnownIndices k = linear_indices(coefficients(t), sds);
    double V = 0.0;
    for (int i = 0; i < d; ++i) V += coefficients(t)[i] * coefficients(t)[i] * sds[i] * sds[i];
    partial_sum += V * k.S1;
    variance_sum += V;
  }
  for (SobolEstimator estimator : {SobolEstimator::kSaltelliJansen, SobolEstimator::kMartinez}) {
    SCOPED_TRACE(name(estimator));
    const SobolIndicesAlongTime s = estimate_sobol_indices_along_time(layout, Y, estimator);
    EXPECT_EQ(s.groups_used, N - 1);
    ASSERT_EQ(s.S1.rows(), d);
    ASSERT_EQ(s.S1.cols(), T);
    for (int t = 0; t + 1 < T; ++t) {
      const KnownIndices k = linear_indices(coefficients(times[t]), sds);
      for (int i = 0; i < d; ++i) {
        EXPECT_NEAR(s.S1(i, t), k.S1[i], 0.02) << "S1 " << i << " t " << times[t];
        EXPECT_NEAR(s.ST(i, t), k.ST[i], 0.02) << "ST " << i << " t " << times[t];
      }
      // Each column is the single-output estimate on the same groups.
      Eigen::VectorXd column = Y.col(t);
      column[7 * (d + 2)] = kNaN;
      SobolOptions options;
      options.estimator = estimator;
      options.bootstrap_resamples = 0;
      const SobolIndices single = estimate_sobol_indices(layout, column, options);
      EXPECT_LT((single.S1 - s.S1.col(t)).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((single.ST - s.ST.col(t)).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_NEAR(single.variance, s.variance[t], 1e-12 * single.variance);
    }
    // The constant output: zero variance, NaN indices, no weight.
    EXPECT_EQ(s.variance[T - 1], 0.0);
    EXPECT_TRUE(s.S1.col(T - 1).array().isNaN().all() && s.ST.col(T - 1).array().isNaN().all());
    const Eigen::VectorXd weights = s.variance.head(T - 1);
    const Eigen::VectorXd weighted_S1 = s.S1.leftCols(T - 1) * weights / weights.sum();
    const Eigen::VectorXd weighted_ST = s.ST.leftCols(T - 1) * weights / weights.sum();
    for (int i = 0; i < d; ++i) {
      EXPECT_NEAR(s.aggregated_S1[i], weighted_S1[i], 1e-12);
      EXPECT_NEAR(s.aggregated_ST[i], weighted_ST[i], 1e-12);
      EXPECT_NEAR(s.aggregated_S1[i], partial_sum[i] / variance_sum, 0.02) << i;
      EXPECT_NEAR(s.aggregated_ST[i], partial_sum[i] / variance_sum, 0.02) << i;
    }
  }
}

}  // namespace
}  // namespace rover::study
