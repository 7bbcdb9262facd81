// LARS entry order and hybrid selection on a sparse model in an orthonormal basis.
#include "study/surrogate/lars.hpp"

#include <gtest/gtest.h>

#include "study/surrogate/pce_basis.hpp"
#include "surrogate_test_designs.hpp"

namespace rover::study {
namespace {

TEST(Lars, StrongestTermsEnterFirstAndHybridKeepsExactlyThem) {
  const std::vector<Distribution> inputs(3, uniform(0.0, 1.0));
  const std::vector<MultiIndex> basis =
      hyperbolic_multi_indices(3, 4, 1.0, std::vector<bool>(3, true));  // 35 terms
  const DesignMatrix x = testing::to_inputs(testing::latin_hypercube(200, 3, 6), inputs);
  const Eigen::MatrixXd psi = pce_basis_matrix(x, inputs, basis);
  // y = 2 + 3 psi_7 - 1 psi_20 + 0.3 psi_2.
  const Eigen::VectorXd y = 2.0 + 3.0 * psi.col(7).array() - psi.col(20).array() + 0.3 * psi.col(2).array();
  const std::vector<int> order = lars_entry_order(psi, y, 3);
  ASSERT_EQ(order.size(), 3u);
  EXPECT_EQ(order[0], 7);
  EXPECT_EQ(order[1], 20);
  EXPECT_EQ(order[2], 2);
  const double variance = (y.array() - y.mean()).square().mean();
  const SparseSelection s = hybrid_lars(psi, y, variance);
  ASSERT_TRUE(s.ok);
  EXPECT_EQ(s.columns, (std::vector<int>{0, 7, 20, 2}));
  EXPECT_NEAR(s.coefficients(1), 3.0, 1e-12);
  EXPECT_NEAR(s.coefficients(3), 0.3, 1e-12);
  EXPECT_LT(s.corrected_loo, 1e-20);
}

}  // namespace
}  // namespace rover::study
