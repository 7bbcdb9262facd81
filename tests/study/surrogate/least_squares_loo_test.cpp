// The incremental QR least squares of the LARS path against the batch fit,
// and the LOO error against explicit refits.
#include "study/surrogate/least_squares_loo.hpp"

#include <gtest/gtest.h>

#include "surrogate_test_designs.hpp"

namespace rover::study {
namespace {

Eigen::MatrixXd random_matrix(int rows, int cols, std::uint64_t seed) {
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      m(i, j) = testing::hashed_uniform(seed, static_cast<std::uint64_t>(i * cols + j)) - 0.5;
  return m;
}

TEST(LeastSquaresLoo, IncrementalEqualsBatchAtEveryColumnCount) {
  const Eigen::MatrixXd psi = random_matrix(40, 12, 1);
  const Eigen::VectorXd y = random_matrix(40, 1, 2).col(0) + psi.col(3);
  const double variance = (y.array() - y.mean()).square().mean();
  IncrementalLeastSquares incremental(y, variance);
  for (int k = 1; k <= 12; ++k) {
    ASSERT_TRUE(incremental.add_column(psi.col(k - 1)));
    const LeastSquaresLoo a = incremental.fit();
    const LeastSquaresLoo b = least_squares_loo(psi.leftCols(k), y, variance);
    ASSERT_TRUE(a.ok && b.ok);
    EXPECT_LT((a.coefficients - b.coefficients).norm(), 1e-10);
    EXPECT_NEAR(a.corrected_loo, b.corrected_loo, 1e-10 * b.corrected_loo);
  }
  // A column in the span of the others is refused.
  EXPECT_FALSE(incremental.add_column(psi.col(0) - 2.0 * psi.col(5)));
  EXPECT_EQ(incremental.columns(), 12);
}

TEST(LeastSquaresLoo, LeaveOneOutEqualsRefits) {
  const Eigen::MatrixXd psi = random_matrix(20, 4, 3);
  const Eigen::VectorXd y = random_matrix(20, 1, 4).col(0);
  const LeastSquaresLoo fit = least_squares_loo(psi, y, 1.0);
  double sum = 0.0;
  for (int left = 0; left < 20; ++left) {
    Eigen::MatrixXd p(19, 4);
    Eigen::VectorXd v(19);
    for (int r = 0, k = 0; r < 20; ++r)
      if (r != left) p.row(k) = psi.row(r), v(k++) = y(r);
    Eigen::VectorXd c;
    ASSERT_TRUE(least_squares_coefficients(p, v, &c));
    sum += std::pow(y(left) - psi.row(left).dot(c), 2);
  }
  EXPECT_NEAR(fit.relative_loo, sum / 20.0, 1e-12);
  EXPECT_GT(fit.corrected_loo, fit.relative_loo);
}

}  // namespace
}  // namespace rover::study
