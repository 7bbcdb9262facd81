// Polynomial chaos of curves: a family of Ishigami functions indexed by a
// "time" t, whose exact indices, means, sds and aggregated indices are known
// for every t, plus constant samples and refused input.
#include "study/surrogate/pce_curves.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <boost/math/constants/constants.hpp>
#include <gtest/gtest.h>

#include "study/estimators/test_models.hpp"
#include "study/surrogate/pce_basis.hpp"
#include "surrogate_test_designs.hpp"

namespace rover::study {
namespace {

constexpr double kPi = boost::math::constants::pi<double>();
constexpr int kSamples = 12;

// Ishigami's a and b along the curve (b quadratic in t, so that the centred
// curves have rank 3); the last sample is constant (a column of 3).
double a_of(int t) { return 7.0 * t / (kSamples - 2); }
double b_of(int t) { return 0.1 * std::pow(static_cast<double>(t) / (kSamples - 2), 2); }

double ishigami_variance(double a, double b) {
  const double pi4 = std::pow(kPi, 4);
  return a * a / 8.0 + b * pi4 / 5.0 + b * b * pi4 * pi4 / 18.0 + 0.5;
}

Eigen::MatrixXd curves(const DesignMatrix& x) {
  Eigen::MatrixXd y(x.rows(), kSamples);
  for (Eigen::Index r = 0; r < x.rows(); ++r) {
    for (int t = 0; t < kSamples - 1; ++t) y(r, t) = ishigami(x.row(r).data(), a_of(t), b_of(t));
    y(r, kSamples - 1) = 3.0;
  }
  return y;
}

TEST(PolynomialChaosCurves, IshigamiFamilyIndicesPerSampleAndAggregated) {
  const std::vector<Distribution> inputs(3, uniform(-kPi, kPi));
  const DesignMatrix x = testing::to_inputs(testing::latin_hypercube(500, 3, 12), inputs);
  const PolynomialChaosCurves c = fit_polynomial_chaos_curves(x, curves(x), inputs, {}, "family");
  const CurveSobolIndices s = curve_sobol_indices(c);
  double worst = 0.0, v_sum = 0.0;
  Eigen::Vector3d v1 = Eigen::Vector3d::Zero(), vt = Eigen::Vector3d::Zero();
  for (int t = 0; t < kSamples - 1; ++t) {
    ASSERT_TRUE(s.defined[t]);
    const KnownIndices exact = ishigami_indices(a_of(t), b_of(t));
    const double v = ishigami_variance(a_of(t), b_of(t));
    EXPECT_NEAR(s.mean(t), a_of(t) / 2.0, 0.01) << "t " << t;
    EXPECT_NEAR(s.sd(t), std::sqrt(v), 0.01 * std::sqrt(v)) << "t " << t;
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(s.S1(t, i), exact.S1(i), 0.01) << "t " << t << " x" << i + 1;
      EXPECT_NEAR(s.ST(t, i), exact.ST(i), 0.01) << "t " << t << " x" << i + 1;
      worst = std::max({worst, std::abs(s.S1(t, i) - exact.S1(i)), std::abs(s.ST(t, i) - exact.ST(i))});
    }
    v1 += v * exact.S1;
    vt += v * exact.ST;
    v_sum += v;
  }
  EXPECT_FALSE(s.defined[kSamples - 1]);
  EXPECT_DOUBLE_EQ(s.mean(kSamples - 1), 3.0);
  EXPECT_EQ(s.sd(kSamples - 1), 0.0);
  EXPECT_TRUE(s.S1.allFinite());
  EXPECT_TRUE(s.aggregated_defined);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.aggregated_S1(i), v1(i) / v_sum, 0.01);
    EXPECT_NEAR(s.aggregated_ST(i), vt(i) / v_sum, 0.01);
  }
  std::printf("curves: %d components, %zu shared terms, min Q2_LOO %.6f, largest index error %.5f\n",
              c.components, c.multi_indices.size(), c.q2_loo.minCoeff(), worst);
  EXPECT_TRUE(c.warning.empty()) << c.warning;
  // The surrogate reproduces held-out curves.
  const DesignMatrix x_test = testing::to_inputs(testing::monte_carlo(200, 3, 8), inputs);
  const Eigen::MatrixXd error = c.evaluate(x_test) - curves(x_test);
  EXPECT_LT(std::sqrt(error.squaredNorm() / static_cast<double>(error.size())), 0.05);
  PolynomialChaosCurves validated = c;
  validate_polynomial_chaos_curves(x_test, curves(x_test), 0.95, &validated);
  EXPECT_EQ(validated.test_points, 200);
  EXPECT_GT(validated.q2_test.head(kSamples - 1).minCoeff(), 0.999);
  EXPECT_TRUE(std::isnan(validated.q2_test(kSamples - 1)));  // the constant sample: no spread, Q2 undefined
  EXPECT_TRUE(validated.warning.empty()) << validated.warning;
}

TEST(PolynomialChaosCurves, FewRunsWarnNamingTheOutputAndTheWorstSample) {
  const std::vector<Distribution> inputs(3, uniform(-kPi, kPi));
  const DesignMatrix x = testing::to_inputs(testing::latin_hypercube(25, 3, 6), inputs);
  PolynomialChaosCurves c = fit_polynomial_chaos_curves(x, curves(x), inputs, {}, "family");
  const DesignMatrix x_test = testing::to_inputs(testing::monte_carlo(100, 3, 3), inputs);
  validate_polynomial_chaos_curves(x_test, curves(x_test), 0.95, &c);
  EXPECT_NE(c.warning.find("'family' is not accurate enough"), std::string::npos) << c.warning;
  EXPECT_NE(c.warning.find("try a larger N"), std::string::npos);
  EXPECT_TRUE(c.q2_test.head(kSamples - 1).allFinite());  // the last sample is constant
}

TEST(PolynomialChaosCurves, PolynomialCurvesReproducedExactly) {
  const std::vector<Distribution> inputs{uniform(0.0, 2.0), normal(1.0, 0.2)};
  const std::vector<MultiIndex> terms{{0, 0}, {1, 0}, {0, 1}, {2, 1}};
  Eigen::MatrixXd c_true(4, 5);
  c_true << 1, 2, 3, 4, 5,  //
      0.5, -0.5, 1, 0, 2,   //
      0, 1, 1, 0.3, -1,     //
      0.2, 0.2, 0, -0.4, 1;
  const DesignMatrix x = testing::to_inputs(testing::latin_hypercube(60, 2, 5), inputs);
  const Eigen::MatrixXd y = pce_basis_matrix(x, inputs, terms) * c_true;
  // Every component (the centred curves have rank 3), total-degree basis.
  PolynomialChaosCurvesSettings s;
  s.explained_variance = 1.0;
  s.pce.q_norm = 1.0;
  const PolynomialChaosCurves c = fit_polynomial_chaos_curves(x, y, inputs, s, "poly");
  EXPECT_EQ(c.components, 3);
  for (std::size_t k = 0; k < terms.size(); ++k) {
    const auto found = std::find(c.multi_indices.begin(), c.multi_indices.end(), terms[k]);
    ASSERT_NE(found, c.multi_indices.end()) << "term " << k;
    const Eigen::Index row = found - c.multi_indices.begin();
    for (int t = 0; t < 5; ++t) EXPECT_NEAR(c.coefficients(row, t), c_true(k, t), 1e-10);
  }
  EXPECT_GT(c.q2_loo.minCoeff(), 1.0 - 1e-10);
}

std::string thrown_message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(nothing thrown)";
}

TEST(PolynomialChaosCurves, RefusesBadSettingsAndData) {
  const std::vector<Distribution> inputs(3, uniform(-kPi, kPi));
  const DesignMatrix x = testing::to_inputs(testing::latin_hypercube(40, 3, 1), inputs);
  Eigen::MatrixXd y = curves(x);
  PolynomialChaosCurvesSettings s;
  s.explained_variance = 0.0;
  EXPECT_NE(thrown_message([&] { fit_polynomial_chaos_curves(x, y, inputs, s); })
                .find("explained_variance 0 is outside (0, 1]"),
            std::string::npos);
  s = {};
  s.max_components = 0;
  EXPECT_NE(thrown_message([&] { fit_polynomial_chaos_curves(x, y, inputs, s); }).find("max_components 0"),
            std::string::npos);
  s = {};
  s.pce.q_norm = -1.0;
  EXPECT_NE(thrown_message([&] { fit_polynomial_chaos_curves(x, y, inputs, s); }).find("q_norm -1"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { fit_polynomial_chaos_curves(x, y.topRows(30), inputs, {}); })
                .find("outputs 30 x 12"),
            std::string::npos);
  y(7, 3) = std::nan("");
  EXPECT_NE(thrown_message([&] { fit_polynomial_chaos_curves(x, y, inputs, {}, "slip"); })
                .find("'slip' is not finite at run 7, sample 3"),
            std::string::npos);
}

}  // namespace
}  // namespace rover::study
