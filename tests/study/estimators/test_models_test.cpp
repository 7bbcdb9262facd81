// Analytic sensitivity test models (study/estimators/test_models.cpp): the closed-form
// indices against published values and against the models themselves, whose
// partial variances are integrated by tensor Gauss-Legendre quadrature.
#include "study/estimators/test_models.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <boost/math/constants/constants.hpp>
#include <boost/math/quadrature/gauss.hpp>
#include <gtest/gtest.h>

namespace rover::study {
namespace {

constexpr double kPi = boost::math::constants::pi<double>();

// A 1-D quadrature rule for the uniform distribution on [lo, hi], made of
// Gauss-Legendre rules on `pieces` equal sub-intervals (split at the kink of
// the g-function); the weights sum to 1.
struct Rule {
  std::vector<double> nodes, weights;
};
Rule uniform_rule(double lo, double hi, int pieces) {
  using Gauss = boost::math::quadrature::gauss<double, 20>;
  Rule rule;
  const double width = (hi - lo) / pieces;
  for (int p = 0; p < pieces; ++p) {
    const double centre = lo + (p + 0.5) * width;
    // Boost stores the non-negative abscissas of the symmetric rule.
    for (std::size_t k = 0; k < Gauss::abscissa().size(); ++k) {
      const double x = Gauss::abscissa()[k], w = Gauss::weights()[k] / (2.0 * pieces);
      for (double sign : {-1.0, 1.0}) {
        if (x == 0.0 && sign > 0.0) continue;
        rule.nodes.push_back(centre + sign * 0.5 * width * x);
        rule.weights.push_back(w);
      }
    }
  }
  return rule;
}

// f tabulated on a 3-D tensor grid of one rule per input, with the variance of
// the conditional expectation E[f | x_u] for any subset u of the inputs.
class TensorGrid {
 public:
  template <class Model>
  TensorGrid(const Rule& rule, Model f) : rule_(rule), n_(rule.nodes.size()) {
    values_.resize(n_ * n_ * n_);
    for (std::size_t a = 0; a < n_; ++a)
      for (std::size_t b = 0; b < n_; ++b)
        for (std::size_t c = 0; c < n_; ++c) {
          const std::array<double, 3> x{rule.nodes[a], rule.nodes[b], rule.nodes[c]};
          values_[(a * n_ + b) * n_ + c] = f(x.data());
        }
  }
  // Var(E[f | x_i, i in subset]); subset = {true, true, true} gives Var(f).
  double closed_variance(const std::array<bool, 3>& subset) const {
    // Conditional mean on the grid of the kept inputs (dropped inputs get one node).
    std::array<std::size_t, 3> size{};
    for (int i = 0; i < 3; ++i) size[i] = subset[i] ? n_ : 1;
    std::vector<double> mean(size[0] * size[1] * size[2], 0.0);
    for (std::size_t a = 0; a < n_; ++a)
      for (std::size_t b = 0; b < n_; ++b)
        for (std::size_t c = 0; c < n_; ++c) {
          double w = 1.0;
          const std::array<std::size_t, 3> k{a, b, c};
          std::array<std::size_t, 3> kept{};
          for (int i = 0; i < 3; ++i) {
            if (!subset[i]) w *= rule_.weights[k[i]];
            kept[i] = subset[i] ? k[i] : 0;
          }
          mean[(kept[0] * size[1] + kept[1]) * size[2] + kept[2]] +=
              w * values_[(a * n_ + b) * n_ + c];
        }
    double m1 = 0.0, m2 = 0.0;
    for (std::size_t a = 0; a < size[0]; ++a)
      for (std::size_t b = 0; b < size[1]; ++b)
        for (std::size_t c = 0; c < size[2]; ++c) {
          double w = 1.0;
          const std::array<std::size_t, 3> k{a, b, c};
          for (int i = 0; i < 3; ++i)
            if (subset[i]) w *= rule_.weights[k[i]];
          const double v = mean[(a * size[1] + b) * size[2] + c];
          m1 += w * v;
          m2 += w * v * v;
        }
    return m2 - m1 * m1;
  }
  // Indices by quadrature: S1_i = V_i / V, ST_i = 1 - Var(E[f | x_~i]) / V,
  // S2_ij = Var(E[f | x_i, x_j]) / V - S1_i - S1_j.
  KnownIndices indices() const {
    const double V = closed_variance({true, true, true});
    KnownIndices k;
    k.S1.resize(3);
    k.ST.resize(3);
    k.S2 = Eigen::MatrixXd::Zero(3, 3);
    for (int i = 0; i < 3; ++i) {
      std::array<bool, 3> only{}, others{true, true, true};
      only[i] = true;
      others[i] = false;
      k.S1[i] = closed_variance(only) / V;
      k.ST[i] = 1.0 - closed_variance(others) / V;
    }
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) {
        std::array<bool, 3> pair{};
        pair[i] = pair[j] = true;
        k.S2(i, j) = closed_variance(pair) / V - k.S1[i] - k.S1[j];
      }
    return k;
  }

 private:
  Rule rule_;
  std::size_t n_;
  std::vector<double> values_;
};

void expect_indices_near(const KnownIndices& actual, const KnownIndices& expected,
                         double tolerance) {
  ASSERT_EQ(actual.S1.size(), expected.S1.size());
  for (Eigen::Index i = 0; i < actual.S1.size(); ++i) {
    EXPECT_NEAR(actual.S1[i], expected.S1[i], tolerance) << "S1 " << i;
    EXPECT_NEAR(actual.ST[i], expected.ST[i], tolerance) << "ST " << i;
    for (Eigen::Index j = i + 1; j < actual.S1.size(); ++j)
      EXPECT_NEAR(actual.S2(i, j), expected.S2(i, j), tolerance) << "S2 " << i << j;
  }
}

TEST(TestModels, IshigamiMatchesThePublishedIndices) {
  // Ishigami & Homma (1990), a = 7, b = 0.1 (e.g. Saltelli et al. 2010, Table 3).
  const KnownIndices k = ishigami_indices();
  EXPECT_NEAR(k.S1[0], 0.3139, 5e-5);
  EXPECT_NEAR(k.S1[1], 0.4424, 5e-5);
  EXPECT_EQ(k.S1[2], 0.0);
  EXPECT_NEAR(k.ST[0], 0.5576, 5e-5);
  EXPECT_NEAR(k.ST[1], 0.4424, 5e-5);
  EXPECT_NEAR(k.ST[2], 0.2437, 5e-5);
  EXPECT_NEAR(k.S2(0, 2), 0.2437, 5e-5);
  // The decomposition is complete: S1 + S2 sums to 1 (no third-order term).
  EXPECT_NEAR(k.S1.sum() + k.S2.sum(), 1.0, 1e-14);
}

TEST(TestModels, IshigamiIndicesMatchQuadratureOfTheModel) {
  for (const auto& [a, b] : {std::pair{7.0, 0.1}, std::pair{2.0, 0.3}}) {
    const TensorGrid grid(uniform_rule(-kPi, kPi, 1),
                          [a = a, b = b](const double* x) { return ishigami(x, a, b); });
    SCOPED_TRACE(a);
    expect_indices_near(ishigami_indices(a, b), grid.indices(), 1e-10);
  }
}

TEST(TestModels, SobolGIndicesMatchQuadratureOfTheModel) {
  const std::vector<double> a{0.0, 1.0, 4.5};
  // The kink of |4x - 2| at x = 1/2 is a rule boundary, so the quadrature is exact.
  const TensorGrid grid(uniform_rule(0.0, 1.0, 2), [&](const double* x) { return sobol_g(x, a); });
  expect_indices_near(sobol_g_indices(a), grid.indices(), 1e-12);
}

TEST(TestModels, SobolGValuesAndLimitingCases) {
  // With a_i = 0 a factor is |4x - 2|; one input alone carries all the variance.
  const double x[2] = {0.125, 0.9};
  EXPECT_DOUBLE_EQ(sobol_g(x, {0.0, 0.0}), 1.5 * 1.6);
  const KnownIndices single = sobol_g_indices({0.0});
  EXPECT_DOUBLE_EQ(single.S1[0], 1.0);
  EXPECT_DOUBLE_EQ(single.ST[0], 1.0);
  // Large a_i makes an input unimportant; equal a_i give equal indices.
  const KnownIndices k = sobol_g_indices({0.0, 1.0, 99.0, 99.0});
  EXPECT_GT(k.S1[0], k.S1[1]);
  EXPECT_LT(k.ST[2], 1e-3);
  EXPECT_DOUBLE_EQ(k.S1[2], k.S1[3]);
  for (Eigen::Index i = 0; i < 4; ++i) EXPECT_GE(k.ST[i], k.S1[i]);
}

TEST(TestModels, LinearModelIndicesAreTheVarianceShares) {
  const double x[3] = {1.0, -2.0, 0.5};
  EXPECT_DOUBLE_EQ(linear_model(x, {2.0, 1.0, 4.0}), 2.0 - 2.0 + 2.0);
  const KnownIndices k = linear_indices({1.0, 2.0, 3.0}, {2.0, 1.0, 0.0});
  EXPECT_DOUBLE_EQ(k.S1[0], 0.5);
  EXPECT_DOUBLE_EQ(k.S1[1], 0.5);
  EXPECT_EQ(k.S1[2], 0.0);
  EXPECT_EQ(k.S1, k.ST);  // additive: no interactions
  EXPECT_THROW(linear_indices({1.0}, {1.0, 2.0}), std::invalid_argument);
  EXPECT_THROW(linear_indices({0.0, 1.0}, {1.0, 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace rover::study
