// Morris elementary effects (study/estimators/morris.cpp): the trajectory design's
// structure, exact effects of linear models, screening of the g-function, and
// failed trajectories.
#include "study/estimators/morris.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "study/estimators/test_models.hpp"

namespace rover::study {
namespace {

template <class Model>
Eigen::VectorXd outputs(const MorrisDesign& design, Model f) {
  Eigen::VectorXd y(design.points.rows());
  for (Eigen::Index r = 0; r < y.size(); ++r) y[r] = f(design.points.row(r).data());
  return y;
}

TEST(Morris, TrajectoriesMoveEachInputOnceByHalfTheLevelsOnTheGrid) {
  const int d = 5, r = 40, p = 6;
  const MorrisDesign design = morris_design(d, r, p, 3);
  ASSERT_EQ(design.points.rows(), r * (d + 1));
  ASSERT_EQ(design.points.cols(), d);
  ASSERT_EQ(design.changed_input.size(), static_cast<std::size_t>(r * d));
  ASSERT_EQ(design.step.size(), static_cast<std::size_t>(r * d));
  EXPECT_EQ(design.trajectories, r);
  EXPECT_EQ(design.dimensions, d);
  EXPECT_EQ(design.levels, p);
  int upward = 0;
  for (Eigen::Index row = 0; row < design.points.rows(); ++row)
    for (int i = 0; i < d; ++i) {
      const double level = design.points(row, i) * (p - 1);  // integer in 0 .. p-1
      EXPECT_NEAR(level, std::round(level), 1e-12);
      EXPECT_GE(std::round(level), 0.0);
      EXPECT_LE(std::round(level), p - 1.0);
    }
  for (int t = 0; t < r; ++t) {
    std::set<int> moved;
    for (int k = 0; k < d; ++k) {
      const int move = t * d + k, i = design.changed_input[move];
      const Eigen::Index before = t * (d + 1) + k;
      moved.insert(i);
      EXPECT_NEAR(std::abs(design.step[move]), p / (2.0 * (p - 1)), 1e-15);  // p/2 levels
      upward += design.step[move] > 0;
      for (int j = 0; j < d; ++j)
        EXPECT_NEAR(design.points(before + 1, j) - design.points(before, j),
                    j == i ? design.step[move] : 0.0, 1e-15);
    }
    EXPECT_EQ(moved.size(), static_cast<std::size_t>(d));
  }
  // Up and down equally likely: 200 jumps, mean 100, sd 7.1.
  EXPECT_NEAR(upward, r * d / 2, 30);
  // Deterministic in the seed.
  EXPECT_EQ(morris_design(d, r, p, 3).points, design.points);
  EXPECT_NE(morris_design(d, r, p, 4).points, design.points);
  EXPECT_THROW(morris_design(d, r, 5, 3), std::invalid_argument);
  EXPECT_THROW(morris_design(0, r, 4, 3), std::invalid_argument);
}

// Ishigami's x2 enters as 7 sin^2(x2), of period pi, half its range [-pi, pi]:
// a jump of half the cube would never see it. On the grid of p levels its
// effects are those of the exact jump, and it ranks where its first-order
// index (0.44, the largest) puts it, above x3 (S1 = 0).
TEST(Morris, SeesAnEffectPeriodicInHalfTheRange) {
  const int d = 3, r = 20;
  for (const int p : {4, 6}) {
    const MorrisDesign design = morris_design(d, r, p, 1);
    const auto ishigami = [](const double* u) {
      const double x1 = -M_PI + 2 * M_PI * u[0], x2 = -M_PI + 2 * M_PI * u[1], x3 = -M_PI + 2 * M_PI * u[2];
      return std::sin(x1) + 7.0 * std::sin(x2) * std::sin(x2) + 0.1 * std::pow(x3, 4) * std::sin(x1);
    };
    const MorrisResult m = morris_effects(design, outputs(design, ishigami), {.bootstrap_resamples = 0});
    // A design blind to it gives rounding only (about 1e-15).
    EXPECT_GT(m.mu_star[1], 1.0) << "p " << p;
  }
}

// How many of a design's elementary-effect steps repeat an earlier one: each
// step as (input, its two points in sorted order), read from the points.
int repeated_steps(const MorrisDesign& design) {
  std::set<std::vector<double>> seen;
  const int d = design.dimensions;
  int repeats = 0;
  for (int t = 0; t < design.trajectories; ++t)
    for (int k = 0; k < d; ++k) {
      const auto a = design.points.row(t * (d + 1) + k), b = design.points.row(t * (d + 1) + k + 1);
      std::vector<double> before(a.begin(), a.end()), after(b.begin(), b.end());
      if (after < before) std::swap(before, after);
      std::vector<double> step{static_cast<double>(design.changed_input[static_cast<std::size_t>(t * d + k)])};
      step.insert(step.end(), before.begin(), before.end());
      step.insert(step.end(), after.begin(), after.end());
      repeats += !seen.insert(step).second;
    }
  return repeats;
}

TEST(Morris, CountsTheDistinctStepsOfEachInput) {
  // A step of input i: the levels of the others, and which of the levels / 2
  // pairs {k, k + levels / 2} input i jumps between.
  EXPECT_EQ(distinct_morris_steps(2, 2), 2.0);
  EXPECT_EQ(distinct_morris_steps(1, 4), 2.0);
  EXPECT_EQ(distinct_morris_steps(2, 4), 8.0);
  EXPECT_EQ(distinct_morris_steps(3, 4), 32.0);
  EXPECT_EQ(distinct_morris_steps(3, 6), 108.0);
  EXPECT_EQ(distinct_morris_steps(40, 8), kManySteps);
}

TEST(Morris, NoStepRepeatsUpToTheNumberOfDistinctSteps) {
  struct Size {
    int d, levels, trajectories;
  };
  // Far from the bound, near it and at it (where random draws collide and the
  // design is packed), on two to six levels.
  for (const Size& size : std::vector<Size>{{2, 2, 2}, {1, 4, 2}, {1, 6, 3}, {2, 4, 8}, {2, 4, 6}, {3, 2, 4},
                                            {4, 2, 8}, {3, 4, 32}, {3, 4, 20}, {5, 2, 16}, {2, 6, 18},
                                            {6, 4, 200}, {16, 4, 20}}) {
    for (std::uint64_t seed = 0; seed < 30; ++seed) {
      const MorrisDesign design = morris_design(size.d, size.trajectories, size.levels, seed);
      EXPECT_EQ(repeated_steps(design), 0)
          << size.d << " inputs, " << size.levels << " levels, " << size.trajectories << " trajectories, seed " << seed;
      EXPECT_EQ(morris_design(size.d, size.trajectories, size.levels, seed).points, design.points);
    }
    EXPECT_THROW(morris_design(size.d, static_cast<int>(distinct_morris_steps(size.d, size.levels)) + 1, size.levels, 1),
                 std::invalid_argument);
  }
}

TEST(Morris, APackedDesignKeepsTheExactEffectsOfALinearModel) {
  // Three inputs on two levels: 4 trajectories take every step of every input.
  const std::vector<double> c{2.0, -0.5, 1.25};
  for (std::uint64_t seed = 0; seed < 10; ++seed) {
    const MorrisDesign design = morris_design(3, 4, 2, seed);
    const MorrisResult m = morris_effects(
        design, outputs(design, [&](const double* u) { return linear_model(u, c); }), {});
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(m.mu[i], c[i], 1e-12) << i;
      EXPECT_NEAR(m.mu_star[i], std::abs(c[i]), 1e-12) << i;
      EXPECT_NEAR(m.sigma[i], 0.0, 1e-12) << i;
    }
  }
}

TEST(Morris, LinearModelEffectsAreExactAndUnscattered) {
  const std::vector<double> c{3.0, -1.5, 0.25, 0.0};
  const MorrisDesign design = morris_design(4, 20, 4, 8);
  const MorrisResult m = morris_effects(
      design, outputs(design, [&](const double* u) { return linear_model(u, c); }), {});
  EXPECT_EQ(m.trajectories_used, 20);
  EXPECT_TRUE(m.dropped_trajectories.empty());
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(m.mu[i], c[i], 1e-12) << i;
    EXPECT_NEAR(m.mu_star[i], std::abs(c[i]), 1e-12) << i;
    EXPECT_NEAR(m.sigma[i], 0.0, 1e-12) << i;
    EXPECT_NEAR(m.mu_star_lower[i], std::abs(c[i]), 1e-12) << i;
    EXPECT_NEAR(m.mu_star_upper[i], std::abs(c[i]), 1e-12) << i;
  }
  EXPECT_EQ(m.ranking, (std::vector<int>{0, 1, 2, 3}));
}

TEST(Morris, AnInputOutsideTheModelHasNoEffectAndInteractionsShowInSigma) {
  // f = u0 u1 + u2^2: input 3 does not enter; u0 and u1 interact.
  auto f = [](const double* u) { return u[0] * u[1] + u[2] * u[2]; };
  const MorrisDesign design = morris_design(4, 30, 4, 2);
  const MorrisResult m = morris_effects(design, outputs(design, f), {});
  EXPECT_EQ(m.mu_star[3], 0.0);
  EXPECT_EQ(m.sigma[3], 0.0);
  EXPECT_EQ(m.mu_star_lower[3], 0.0);
  EXPECT_EQ(m.mu_star_upper[3], 0.0);
  EXPECT_EQ(m.ranking.back(), 3);
  // The effect of u0 is u1 (on the grid {1/8, 3/8, 5/8, 7/8}); it varies, so sigma > 0.
  EXPECT_GT(m.sigma[0], 0.1);
  EXPECT_GT(m.mu_star[0], 0.1);
  EXPECT_LE(m.mu_star[0], 7.0 / 8.0);
  EXPECT_LE(m.mu_star_lower[0], m.mu_star[0]);
  EXPECT_GE(m.mu_star_upper[0], m.mu_star[0]);
}

TEST(Morris, RanksTheGFunctionInputsInTheOrderOfTheirCoefficients) {
  const std::vector<double> a{0.0, 1.0, 4.5, 9.0, 99.0, 99.0, 99.0, 99.0};
  const MorrisDesign design = morris_design(8, 50, 4, 12);
  const MorrisResult m =
      morris_effects(design, outputs(design, [&](const double* u) { return sobol_g(u, a); }), {});
  EXPECT_EQ(std::vector<int>(m.ranking.begin(), m.ranking.begin() + 4),
            (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(std::set<int>(m.ranking.begin() + 4, m.ranking.end()), (std::set<int>{4, 5, 6, 7}));
  // The important inputs are separated from the negligible ones by their intervals.
  for (int i = 4; i < 8; ++i) EXPECT_LT(m.mu_star_upper[i], m.mu_star_lower[3]) << i;
}

TEST(Morris, FailedRunsDropTheirTrajectories) {
  const std::vector<double> c{1.0, 2.0, -3.0};
  const MorrisDesign design = morris_design(3, 10, 4, 5);
  Eigen::VectorXd y = outputs(design, [&](const double* u) { return linear_model(u, c); });
  const Eigen::VectorXd clean = y;
  y[2 * 4 + 1] = std::numeric_limits<double>::quiet_NaN();   // trajectory 2
  y[7 * 4 + 3] = std::numeric_limits<double>::infinity();    // trajectory 7
  const MorrisResult m = morris_effects(design, y, {});
  EXPECT_EQ(m.dropped_trajectories, (std::vector<int>{2, 7}));
  EXPECT_EQ(m.trajectories_used, 8);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(m.mu[i], c[i], 1e-12);
  // g-function: the same as the design without those trajectories.
  const std::vector<double> a{0.0, 1.0, 9.0};
  Eigen::VectorXd g = outputs(design, [&](const double* u) { return sobol_g(u, a); });
  const MorrisResult all = morris_effects(design, g, {});
  g[2 * 4] = std::numeric_limits<double>::quiet_NaN();
  const MorrisResult without = morris_effects(design, g, {});
  MorrisDesign reduced = design;
  reduced.trajectories = 9;
  reduced.points.resize(9 * 4, 3);
  reduced.changed_input.clear();
  reduced.step.clear();
  Eigen::VectorXd g_reduced(9 * 4);
  for (int t = 0, kept = 0; t < 10; ++t) {
    if (t == 2) continue;
    reduced.points.middleRows(kept * 4, 4) = design.points.middleRows(t * 4, 4);
    g_reduced.segment(kept * 4, 4) = g.segment(t * 4, 4);
    for (int k = 0; k < 3; ++k) {
      reduced.changed_input.push_back(design.changed_input[t * 3 + k]);
      reduced.step.push_back(design.step[t * 3 + k]);
    }
    ++kept;
  }
  const MorrisResult reference = morris_effects(reduced, g_reduced, {});
  EXPECT_LT((without.mu_star - reference.mu_star).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_LT((without.sigma - reference.sigma).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_GT((without.mu_star - all.mu_star).cwiseAbs().maxCoeff(), 0.0);
  // Nothing left: an error, not NaN effects.
  EXPECT_THROW(morris_effects(design, Eigen::VectorXd::Constant(y.size(), std::nan("")), {}),
               std::invalid_argument);
  EXPECT_THROW(morris_effects(design, Eigen::VectorXd::Zero(5), {}), std::invalid_argument);
}

}  // namespace
}  // namespace rover::study
