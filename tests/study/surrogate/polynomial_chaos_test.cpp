// Sparse polynomial chaos: exact reproduction of a polynomial in the basis,
// Sobol' indices of the Ishigami and g-functions against their exact values,
// bootstrap intervals, validation and refused settings.
#include "study/surrogate/polynomial_chaos.hpp"

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <boost/math/constants/constants.hpp>
#include <gtest/gtest.h>

#include "study/estimators/test_models.hpp"
#include "study/estimators/work_stopped.hpp"
#include "study/surrogate/lars.hpp"
#include "study/surrogate/multi_index_set.hpp"
#include "study/surrogate/pce_basis.hpp"
#include "study/surrogate/pce_sobol.hpp"
#include "surrogate_test_designs.hpp"

namespace rover::study {
namespace {

using testing::latin_hypercube;
using testing::to_inputs;

constexpr double kPi = boost::math::constants::pi<double>();

Eigen::VectorXd apply(const DesignMatrix& x, double (*f)(const double*)) {
  Eigen::VectorXd y(x.rows());
  for (Eigen::Index r = 0; r < x.rows(); ++r) y(r) = f(x.row(r).data());
  return y;
}

double ishigami_default(const double* x) { return ishigami(x); }

const std::vector<double> kGCoefficients{0.0, 1.0, 4.5, 9.0, 99.0, 99.0, 99.0, 99.0};
double g_function(const double* x) { return sobol_g(x, kGCoefficients); }

// Four kinds of input, and a sparse polynomial in their orthonormal basis.
std::vector<Distribution> mixed_inputs() {
  return {uniform(-1.0, 3.0), normal(2.0, 0.5), lognormal(0.1, 0.3), log_uniform(0.1, 10.0)};
}
std::vector<MultiIndex> true_terms() {
  return {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 2, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 3}, {1, 1, 0, 0}, {0, 1, 0, 2}};
}
Eigen::VectorXd true_coefficients() {
  Eigen::VectorXd c(7);
  c << 4.0, 1.5, -0.8, 0.6, 0.3, 0.7, -0.45;
  return c;
}

void expect_exact_polynomial(BasisSelection selection) {
  const auto inputs = mixed_inputs();
  const DesignMatrix x = to_inputs(latin_hypercube(120, 4, 11), inputs);
  const Eigen::VectorXd y = pce_basis_matrix(x, inputs, true_terms()) * true_coefficients();
  PolynomialChaosSettings s;
  s.max_degree = 3;
  s.q_norm = 1.0;
  s.adaptive_degree = false;
  s.selection = selection;
  const PolynomialChaosExpansion e = fit_polynomial_chaos(x, y, inputs, s, "poly");
  // Every true term with its coefficient; every other selected term ~0.
  for (std::size_t t = 0; t < true_terms().size(); ++t) {
    bool found = false;
    for (std::size_t k = 0; k < e.multi_indices.size(); ++k)
      if (e.multi_indices[k] == true_terms()[t]) {
        found = true;
        EXPECT_NEAR(e.coefficients(k), true_coefficients()(t), 1e-10);
      }
    EXPECT_TRUE(found) << "term " << t;
  }
  const PceSobolIndices exact = pce_sobol_indices(true_terms(), true_coefficients());
  const PceSobolIndices fitted = pce_sobol_indices(e);
  ASSERT_TRUE(fitted.defined);
  EXPECT_NEAR(fitted.mean, 4.0, 1e-10);
  EXPECT_NEAR(fitted.variance, exact.variance, 1e-10);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(fitted.S1(i), exact.S1(i), 1e-10);
    EXPECT_NEAR(fitted.ST(i), exact.ST(i), 1e-10);
    for (int j = i + 1; j < 4; ++j) EXPECT_NEAR(fitted.S2(i, j), exact.S2(i, j), 1e-10);
  }
  EXPECT_GT(e.validation.q2_loo, 1.0 - 1e-12);
  EXPECT_TRUE(e.validation.warning.empty()) << e.validation.warning;
}

TEST(PolynomialChaos, ReproducesAPolynomialInItsBasisByLars) {
  expect_exact_polynomial(BasisSelection::kHybridLars);
}
TEST(PolynomialChaos, ReproducesAPolynomialInItsBasisByLeastSquares) {
  expect_exact_polynomial(BasisSelection::kFullLeastSquares);
}

TEST(PolynomialChaos, LinearModelOfNormalInputsHasExactIndices) {
  const std::vector<double> coefficients{1.0, -1.0, 3.0}, sds{1.0, 2.0, 0.5};
  const std::vector<Distribution> inputs{normal(0.0, 1.0), normal(0.0, 2.0), normal(0.0, 0.5)};
  const DesignMatrix x = to_inputs(latin_hypercube(50, 3, 31), inputs);
  Eigen::VectorXd y(50);
  for (int r = 0; r < 50; ++r) y(r) = linear_model(x.row(r).data(), coefficients);
  const PceSobolIndices s = pce_sobol_indices(fit_polynomial_chaos(x, y, inputs, {}, "linear"));
  const KnownIndices exact = linear_indices(coefficients, sds);
  ASSERT_TRUE(s.defined);
  EXPECT_NEAR(s.mean, 0.0, 1e-10);
  EXPECT_NEAR(s.variance, 1.0 + 4.0 + 2.25, 1e-10);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.S1(i), exact.S1(i), 1e-10);
    EXPECT_NEAR(s.ST(i), exact.ST(i), 1e-10);
  }
}

TEST(PolynomialChaos, ClosedFormIndicesOfKnownCoefficients) {
  // Y = 1 + 2 psi_1(x1) + 3 psi_1(x2) + 1 psi_1(x1) psi_1(x2): V = 4 + 9 + 1.
  const std::vector<MultiIndex> terms{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  Eigen::VectorXd c(4);
  c << 1.0, 2.0, 3.0, 1.0;
  const PceSobolIndices s = pce_sobol_indices(terms, c);
  ASSERT_TRUE(s.defined);
  EXPECT_DOUBLE_EQ(s.mean, 1.0);
  EXPECT_DOUBLE_EQ(s.variance, 14.0);
  EXPECT_DOUBLE_EQ(s.S1(0), 4.0 / 14.0);
  EXPECT_DOUBLE_EQ(s.ST(1), 10.0 / 14.0);
  EXPECT_DOUBLE_EQ(s.ST(2), 0.0);
  EXPECT_DOUBLE_EQ(s.S2(0, 1), 1.0 / 14.0);
  EXPECT_DOUBLE_EQ(s.S2_closed(0, 1), 1.0);
}

TEST(PolynomialChaos, IshigamiIndicesFrom500Runs) {
  const std::vector<Distribution> inputs(3, uniform(-kPi, kPi));
  const DesignMatrix x = to_inputs(latin_hypercube(500, 3, 2024), inputs);
  const Eigen::VectorXd y = apply(x, ishigami_default);
  const PolynomialChaosExpansion e = fit_polynomial_chaos(x, y, inputs, {}, "ishigami");
  const PceSobolIndices s = pce_sobol_indices(e);
  const KnownIndices exact = ishigami_indices();
  ASSERT_TRUE(s.defined);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.S1(i), exact.S1(i), 0.01) << "S1 of x" << i + 1;
    EXPECT_NEAR(s.ST(i), exact.ST(i), 0.01) << "ST of x" << i + 1;
    std::printf("ishigami x%d: S1 %.5f (exact %.5f), ST %.5f (exact %.5f)\n", i + 1, s.S1(i),
                exact.S1(i), s.ST(i), exact.ST(i));
  }
  EXPECT_NEAR(s.S2(0, 2), exact.S2(0, 2), 0.01);
  std::printf("ishigami: degree %d, %zu of %d terms, Q2_LOO %.6f\n", e.degree,
              e.multi_indices.size(), e.candidate_terms, e.validation.q2_loo);
  EXPECT_GT(e.validation.q2_loo, 0.99);
  // Held-out validation on fresh points.
  PolynomialChaosExpansion validated = e;
  const DesignMatrix x_test = to_inputs(latin_hypercube(400, 3, 77), inputs);
  validate_polynomial_chaos(x_test, apply(x_test, ishigami_default), 0.95, &validated);
  EXPECT_EQ(validated.validation.test_points, 400);
  EXPECT_GT(validated.validation.q2_test, 0.99);
  EXPECT_TRUE(validated.validation.warning.empty());
}

TEST(PolynomialChaos, SobolGFunctionIndicesIn8DimensionsFrom1000Runs) {
  const std::vector<Distribution> inputs(8, uniform(0.0, 1.0));
  const DesignMatrix x = to_inputs(latin_hypercube(1000, 8, 7), inputs);
  const Eigen::VectorXd y = apply(x, g_function);
  PolynomialChaosSettings settings;
  settings.q_norm = 0.5;
  const PolynomialChaosExpansion e = fit_polynomial_chaos(x, y, inputs, settings, "g");
  const PceSobolIndices s = pce_sobol_indices(e);
  const KnownIndices exact = sobol_g_indices(kGCoefficients);
  ASSERT_TRUE(s.defined);
  double worst = 0.0;
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(s.S1(i), exact.S1(i), 0.02) << "S1 of x" << i + 1;
    EXPECT_NEAR(s.ST(i), exact.ST(i), 0.02) << "ST of x" << i + 1;
    worst = std::max({worst, std::abs(s.S1(i) - exact.S1(i)), std::abs(s.ST(i) - exact.ST(i))});
  }
  std::printf("g-function: degree %d, %zu of %d terms, Q2_LOO %.5f, largest index error %.5f\n",
              e.degree, e.multi_indices.size(), e.candidate_terms, e.validation.q2_loo, worst);
}

TEST(PolynomialChaos, BootstrapIntervalsAreDeterministicAndCoverTheEstimate) {
  const std::vector<Distribution> inputs(3, uniform(-kPi, kPi));
  const DesignMatrix x = to_inputs(latin_hypercube(300, 3, 5), inputs);
  const Eigen::VectorXd y = apply(x, ishigami_default);
  const PolynomialChaosExpansion e = fit_polynomial_chaos(x, y, inputs, {}, "ishigami");
  const PceSobolIndices s = pce_sobol_indices(e);
  PceBootstrapSettings b;
  b.resamples = 100;
  b.seed = 42;
  const PceSobolIntervals a1 = bootstrap_pce_sobol(e, x, y, b);
  const PceSobolIntervals a2 = bootstrap_pce_sobol(e, x, y, b);
  EXPECT_EQ(a1.resamples_used + a1.resamples_skipped, 100);
  EXPECT_EQ(a1.S1_lower, a2.S1_lower);
  EXPECT_EQ(a1.ST_upper, a2.ST_upper);
  const KnownIndices exact = ishigami_indices();
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(a1.S1_lower(i), a1.S1_upper(i));
    EXPECT_LE(a1.S1_lower(i), s.S1(i) + 0.01);
    EXPECT_GE(a1.S1_upper(i), s.S1(i) - 0.01);
    EXPECT_LT(a1.S1_upper(i) - a1.S1_lower(i), 0.1);
    EXPECT_NEAR(0.5 * (a1.ST_lower(i) + a1.ST_upper(i)), exact.ST(i), 0.05);
  }
  b.seed = 43;
  EXPECT_NE(bootstrap_pce_sobol(e, x, y, b).S1_lower, a1.S1_lower);
}

// Which indices the selected terms fix at 0 or 1, from the terms alone.
TEST(PolynomialChaos, IndicesFixedBySelectionFollowTheTermsSupports) {
  const auto fixed = [](const std::vector<MultiIndex>& terms) { return pce_indices_fixed_by_selection(terms, 2); };
  // x1 alone: both indices of both inputs fixed (x1 at 1, x2 at 0).
  PceIndicesFixedBySelection f = fixed({{0, 0}, {1, 0}, {3, 0}});
  EXPECT_EQ(f.S1, (std::vector<bool>{true, true}));
  EXPECT_EQ(f.ST, (std::vector<bool>{true, true}));
  // Both inputs alone: nothing fixed.
  f = fixed({{0, 0}, {1, 0}, {0, 2}});
  EXPECT_FALSE(f.any());
  // Only an interaction: both S1 fixed at 0, both ST at 1.
  f = fixed({{0, 0}, {1, 1}});
  EXPECT_EQ(f.S1, (std::vector<bool>{true, true}));
  EXPECT_EQ(f.ST, (std::vector<bool>{true, true}));
  // x1 alone and with x2: S1 of x2 is 0, ST of x1 is 1; the rest can move.
  f = fixed({{0, 0}, {2, 0}, {1, 1}});
  EXPECT_EQ(f.S1, (std::vector<bool>{false, true}));
  EXPECT_EQ(f.ST, (std::vector<bool>{true, false}));
}

// An expansion of one input's terms has zero-width bootstrap intervals that
// its result marks, and warns of once its Q2 is below the threshold.
TEST(PolynomialChaos, ZeroWidthIntervalsOfTheSelectionAreMarked) {
  const std::vector<Distribution> inputs(2, uniform(0.0, 1.0));
  const DesignMatrix x = to_inputs(latin_hypercube(40, 2, 7), inputs);
  Eigen::VectorXd y(40);
  for (int r = 0; r < 40; ++r) y(r) = 1.0 + 2.0 * x(r, 0);
  const PolynomialChaosExpansion e = fit_polynomial_chaos(x, y, inputs, {}, "line");
  PceBootstrapSettings b;
  b.resamples = 50;
  const PceSobolIntervals ci = bootstrap_pce_sobol(e, x, y, b);
  EXPECT_DOUBLE_EQ(ci.S1_lower(0), 1.0);
  EXPECT_DOUBLE_EQ(ci.S1_upper(0), 1.0);
  EXPECT_EQ(ci.fixed_by_selection.S1, (std::vector<bool>{true, true}));
  EXPECT_EQ(ci.fixed_by_selection.ST, (std::vector<bool>{true, true}));
  const PceSobolIntervals ishigami_ci = [&] {
    const std::vector<Distribution> three(3, uniform(-kPi, kPi));
    const DesignMatrix xi = to_inputs(latin_hypercube(300, 3, 5), three);
    const Eigen::VectorXd yi = apply(xi, ishigami_default);
    return bootstrap_pce_sobol(fit_polynomial_chaos(xi, yi, three, {}, "ishigami"), xi, yi, b);
  }();
  EXPECT_EQ(ishigami_ci.fixed_by_selection.ST, (std::vector<bool>{false, false, false}));
}

TEST(PolynomialChaos, ConstantOutputHasUndefinedIndicesNotNaN) {
  const std::vector<Distribution> inputs(2, uniform(0.0, 1.0));
  const DesignMatrix x = to_inputs(latin_hypercube(30, 2, 3), inputs);
  const Eigen::VectorXd y = Eigen::VectorXd::Constant(30, 2.5);
  const PolynomialChaosExpansion e = fit_polynomial_chaos(x, y, inputs, {}, "flat");
  EXPECT_TRUE(e.constant_output);
  EXPECT_NE(e.validation.warning.find("'flat' is constant"), std::string::npos) << e.validation.warning;
  const PceSobolIndices s = pce_sobol_indices(e);
  EXPECT_FALSE(s.defined);
  EXPECT_FALSE(s.undefined_reason.empty());
  EXPECT_EQ(s.S1.size(), 0);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_THROW(bootstrap_pce_sobol(e, x, y, {}), std::invalid_argument);
}

TEST(PolynomialChaos, FixedInputGetsNoTermsAndZeroIndices) {
  const std::vector<Distribution> inputs{uniform(0.0, 1.0), fixed_value(2.0), uniform(0.0, 1.0)};
  const DesignMatrix x = to_inputs(latin_hypercube(60, 3, 9), inputs);
  Eigen::VectorXd y(60);
  for (int r = 0; r < 60; ++r) y(r) = x(r, 0) * x(r, 0) + 0.5 * x(r, 2) + x(r, 1);
  const PceSobolIndices s = pce_sobol_indices(fit_polynomial_chaos(x, y, inputs, {}, "y"));
  ASSERT_TRUE(s.defined);
  EXPECT_DOUBLE_EQ(s.ST(1), 0.0);
  EXPECT_NEAR(s.S1(0) + s.S1(2), 1.0, 1e-10);
}

TEST(PolynomialChaos, CandidateBasisSizeIsCapped) {
  // 30 inputs: the degree-1 set has 31 terms, the degree-2 set (q 0.75) 61.
  const std::vector<Distribution> inputs(30, uniform(0.0, 1.0));
  const DesignMatrix x = to_inputs(latin_hypercube(80, 30, 2), inputs);
  Eigen::VectorXd y(80);
  for (int r = 0; r < 80; ++r) y(r) = x.row(r).sum() + x(r, 0) * x(r, 0);
  PolynomialChaosSettings s;
  s.max_candidate_terms = 50;
  const PolynomialChaosExpansion e = fit_polynomial_chaos(x, y, inputs, s, "wide");
  EXPECT_EQ(e.degree, 1);
  EXPECT_EQ(e.candidate_terms, 31);
  s.max_candidate_terms = 20;
  EXPECT_THROW(fit_polynomial_chaos(x, y, inputs, s, "wide"), std::invalid_argument);
}

TEST(PolynomialChaos, LowAccuracyFlagsAWarningNamingTheOutput) {
  const std::vector<Distribution> inputs(3, uniform(-kPi, kPi));
  const DesignMatrix x = to_inputs(latin_hypercube(12, 3, 4), inputs);
  const PolynomialChaosExpansion e =
      fit_polynomial_chaos(x, apply(x, ishigami_default), inputs, {}, "ishigami_small");
  EXPECT_LT(e.validation.q2_loo, 0.95);
  EXPECT_NE(e.validation.warning.find("'ishigami_small'"), std::string::npos);
  EXPECT_NE(e.validation.warning.find("larger N"), std::string::npos) << e.validation.warning;
}

// Q^2 of the expansion on fresh Monte Carlo points of Ishigami: its true
// predictivity, independent of the leave-one-out estimate.
double true_ishigami_q2(const PolynomialChaosExpansion& e) {
  constexpr int kFreshPoints = 4000;
  const DesignMatrix x = to_inputs(testing::monte_carlo(kFreshPoints, 3, 99), e.inputs);
  SurrogateValidation fresh;
  score_held_out(apply(x, ishigami_default), e.evaluate(x), &fresh);
  return fresh.q2_test;
}

// On small designs the leave-one-out Q2 (terms kept fixed) can be near 1
// while the expansion predicts fresh points worse than their mean. The fit
// is also cross-validated with its terms re-selected in every fold, and is
// trusted only when no Q2 falls below the threshold: then it predicts fresh
// points with a Q2 above 0.9, and every misleading Q2_LOO is caught.
TEST(PolynomialChaos, TheSelectionIsCrossValidatedWithItsTermsReselected) {
  const std::vector<Distribution> inputs(3, uniform(-kPi, kPi));
  int misleading = 0, trusted = 0;
  for (int seed = 1; seed <= 40; ++seed) {
    const int runs = seed <= 20 ? 5 + seed : 3 * seed;  // 6 to 25 runs, then 63 to 120
    const DesignMatrix x = to_inputs(latin_hypercube(runs, 3, seed), inputs);
    PolynomialChaosExpansion e = fit_polynomial_chaos(x, apply(x, ishigami_default), inputs, {}, "y");
    const SurrogateValidation& v = e.validation;
    if (e.constant_output) continue;
    const std::string distrust = surrogate_not_to_trust("y", v);
    const bool validated = v.reselected.folds > 0;
    EXPECT_EQ(validated, v.reselected.why_not.empty()) << "seed " << seed;
    EXPECT_EQ(distrust.empty(), validated && v.reselected.q2 >= kDefaultQ2Threshold && v.q2_loo >= kDefaultQ2Threshold)
        << "seed " << seed << ": " << distrust;
    const double q2_fresh = true_ishigami_q2(e);
    if (v.q2_loo > 0.9 && q2_fresh < 0.0) {
      ++misleading;
      EXPECT_FALSE(distrust.empty()) << "seed " << seed << ": Q2_LOO " << v.q2_loo << " trusted";
    }
    if (distrust.empty()) {
      ++trusted;
      EXPECT_GT(q2_fresh, 0.9) << "seed " << seed << ": trusted, yet poor on fresh points";
    }
    // Fresh points scored as held-out runs decide in place of a cross-validation that could not be done.
    const DesignMatrix x_test = to_inputs(latin_hypercube(50, 3, 1000 + seed), inputs);
    validate_polynomial_chaos(x_test, apply(x_test, ishigami_default), 0.95, &e);
    const bool any_low = e.validation.q2_test < kDefaultQ2Threshold || e.validation.q2_loo < kDefaultQ2Threshold ||
                         (validated && e.validation.reselected.q2 < kDefaultQ2Threshold);
    EXPECT_EQ(surrogate_not_to_trust("y", e.validation).empty(), !any_low) << "seed " << seed;
  }
  EXPECT_GT(misleading, 0) << "no fit where Q2_LOO > 0.9 hid a true Q2 below 0";
  EXPECT_GT(trusted, 5);
  // With 100 runs the selection holds up in cross-validation and on fresh points.
  const DesignMatrix x = to_inputs(latin_hypercube(100, 3, 2024), inputs);
  const PolynomialChaosExpansion e = fit_polynomial_chaos(x, apply(x, ishigami_default), inputs, {}, "y");
  EXPECT_EQ(surrogate_not_to_trust("y", e.validation), "");
  EXPECT_GT(e.validation.reselected.q2, 0.95);
  EXPECT_GT(true_ishigami_q2(e), 0.99);
}

std::string thrown_message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

TEST(PolynomialChaos, RefusesBadSettingsAndData) {
  const std::vector<Distribution> inputs(2, uniform(0.0, 1.0));
  const DesignMatrix x = to_inputs(latin_hypercube(40, 2, 1), inputs);
  const Eigen::VectorXd y = x.col(0) + x.col(1);
  const auto fit = [&](const PolynomialChaosSettings& s) { fit_polynomial_chaos(x, y, inputs, s); };
  PolynomialChaosSettings s;
  s.max_degree = 0;
  EXPECT_NE(thrown_message([&] { fit(s); }).find("max_degree 0 is outside [1, 20]"), std::string::npos);
  s.max_degree = 21;
  EXPECT_NE(thrown_message([&] { fit(s); }).find("max_degree 21"), std::string::npos);
  s = {};
  s.q_norm = 0.0;
  EXPECT_NE(thrown_message([&] { fit(s); }).find("q_norm 0 is outside (0, 1]"), std::string::npos);
  s.q_norm = 1.5;
  EXPECT_NE(thrown_message([&] { fit(s); }).find("q_norm 1.5"), std::string::npos);
  s = {};
  s.min_degree = 5;
  s.max_degree = 3;
  EXPECT_NE(thrown_message([&] { fit(s); }).find("min_degree 5"), std::string::npos);
  // Too few runs: 3 runs, the sparse basis needs 2 + 1 + 2.
  EXPECT_NE(thrown_message([&] {
              fit_polynomial_chaos(x.topRows(3), y.head(3), inputs, {});
            }).find("needs at least 5"),
            std::string::npos);
  s = {};
  s.selection = BasisSelection::kFullLeastSquares;
  s.adaptive_degree = false;
  s.max_degree = 8;  // 45 terms > 40 runs
  s.q_norm = 1.0;
  EXPECT_NE(thrown_message([&] { fit(s); }).find("needs at least 46"), std::string::npos);
  // Mismatched dimensions and failed runs.
  EXPECT_NE(thrown_message([&] { fit_polynomial_chaos(x, y.head(39), inputs, {}); }).find("40 x 2"),
            std::string::npos);
  EXPECT_THROW(fit_polynomial_chaos(x, y, {uniform(0.0, 1.0)}, {}), std::invalid_argument);
  Eigen::VectorXd failed = y;
  failed(17) = std::nan("");
  EXPECT_NE(thrown_message([&] { fit_polynomial_chaos(x, failed, inputs, {}, "slip"); })
                .find("'slip' is not finite at run 17"),
            std::string::npos);
  EXPECT_THROW(fit_polynomial_chaos(x, y, {uniform(1.0, 0.0), uniform(0.0, 1.0)}, {}),
               std::invalid_argument);
  PceBootstrapSettings b;
  b.resamples = 1;
  const PolynomialChaosExpansion e = fit_polynomial_chaos(x, y, inputs, {});
  EXPECT_NE(thrown_message([&] { bootstrap_pce_sobol(e, x, y, b); }).find("resamples 1"),
            std::string::npos);
  b = {};
  b.confidence = 1.0;
  EXPECT_NE(thrown_message([&] { bootstrap_pce_sobol(e, x, y, b); }).find("confidence 1"),
            std::string::npos);
}

// A stop request ends the fit, LARS or least squares, with WorkStopped (not
// an expansion, not an invalid_argument that a study would report as a
// failed QoI); without one the same fit completes.
TEST(PolynomialChaos, AStopRequestEndsTheFit) {
  const std::vector<Distribution> inputs(3, uniform(-kPi, kPi));
  const DesignMatrix x = to_inputs(latin_hypercube(200, 3, 7), inputs);
  const Eigen::VectorXd y = apply(x, ishigami_default);
  std::atomic<bool> stop{true};
  for (const BasisSelection selection : {BasisSelection::kHybridLars, BasisSelection::kFullLeastSquares}) {
    PolynomialChaosSettings s;
    s.max_degree = 6;
    s.selection = selection;
    s.stop = &stop;
    EXPECT_THROW(fit_polynomial_chaos(x, y, inputs, s, "ishigami"), WorkStopped);
    stop = false;
    EXPECT_GT(fit_polynomial_chaos(x, y, inputs, s, "ishigami").validation.q2_loo, 0.5);
    stop = true;
  }
  const Eigen::MatrixXd psi = pce_basis_matrix(x, inputs, hyperbolic_multi_indices(3, 4, 1.0, {true, true, true}));
  EXPECT_THROW(hybrid_lars(psi, y, 13.8, &stop), WorkStopped);
}

}  // namespace
}  // namespace rover::study
