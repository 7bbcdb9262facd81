// K-fold cross-validation of a whole fit (study/surrogate/cross_validation.hpp):
// with one fold per run it is leave-one-out by refits, which for least
// squares must equal the closed-form PRESS of the hat matrix (Allen 1974);
// folds too small to refit on, failing fits and equal values are reported.
#include "study/surrogate/cross_validation.hpp"

#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "study/surrogate/least_squares_loo.hpp"
#include "surrogate_test_designs.hpp"

namespace rover::study {
namespace {

// A straight line plus a quadratic bend and a wiggle, fitted by a line.
Eigen::VectorXd bent_line(const DesignMatrix& x) {
  return (1.0 + 2.0 * x.col(0).array() + 0.7 * x.col(0).array().square() + 0.1 * (9.0 * x.col(0).array()).sin())
      .matrix();
}
Eigen::MatrixXd line_basis(const DesignMatrix& x) {
  Eigen::MatrixXd psi(x.rows(), 2);
  psi.col(0).setOnes();
  psi.col(1) = x.col(0);
  return psi;
}
Eigen::VectorXd fit_line_and_predict(const DesignMatrix& x_train, const Eigen::VectorXd& y_train,
                                     const DesignMatrix& x_test) {
  const Eigen::VectorXd c = line_basis(x_train).colPivHouseholderQr().solve(y_train);
  return line_basis(x_test) * c;
}

TEST(CrossValidation, OneFoldPerRunIsLeaveOneOutAsTheHatMatrixGivesIt) {
  for (const int runs : {5, 8, kCrossValidationFolds}) {
    const DesignMatrix x = testing::latin_hypercube(runs, 1, static_cast<std::uint64_t>(runs));
    const Eigen::VectorXd y = bent_line(x);
    const CrossValidation cv = cross_validate(x, y, 2, fit_line_and_predict);
    ASSERT_EQ(cv.folds, runs) << cv.why_not;
    const double variance = (y.array() - y.mean()).square().mean();
    const LeastSquaresLoo closed_form = least_squares_loo(line_basis(x), y, variance);
    ASSERT_TRUE(closed_form.ok);
    EXPECT_NEAR(cv.q2, 1.0 - closed_form.relative_loo, 1e-12) << runs << " runs";
    EXPECT_LT(cv.q2, 1.0);
  }
}

TEST(CrossValidation, MoreRunsThanFoldsPredictEachRunOnceFromTheOthers) {
  const int runs = 37;
  const DesignMatrix x = testing::latin_hypercube(runs, 1, 5);
  const Eigen::VectorXd y = bent_line(x);
  int fits = 0;
  Eigen::VectorXd seen = Eigen::VectorXd::Zero(runs);
  const CrossValidation cv = cross_validate(x, y, 2, [&](const DesignMatrix& xt, const Eigen::VectorXd& yt,
                                                         const DesignMatrix& xv) {
    ++fits;
    EXPECT_EQ(xt.rows() + xv.rows(), runs);
    EXPECT_LE(xv.rows(), (runs + kCrossValidationFolds - 1) / kCrossValidationFolds);
    for (Eigen::Index r = 0; r < xv.rows(); ++r)
      for (Eigen::Index i = 0; i < runs; ++i)
        if (x(i, 0) == xv(r, 0)) seen(i) += 1.0;
    return fit_line_and_predict(xt, yt, xv);
  });
  EXPECT_EQ(cv.folds, kCrossValidationFolds);
  EXPECT_EQ(fits, kCrossValidationFolds);
  EXPECT_TRUE((seen.array() == 1.0).all());
  EXPECT_GT(cv.q2, 0.9);  // the line explains most of the bent line
}

TEST(CrossValidation, SaysWhyItCouldNotBeDone) {
  const DesignMatrix x = testing::latin_hypercube(6, 1, 3);
  const CrossValidation small = cross_validate(x, bent_line(x), 6, fit_line_and_predict);
  EXPECT_EQ(small.folds, 0);
  EXPECT_EQ(small.why_not, "a fold of 6 runs leaves 5 to refit on, and the fit needs 6");
  const CrossValidation failing = cross_validate(
      x, bent_line(x), 2, [](const DesignMatrix&, const Eigen::VectorXd&, const DesignMatrix&) -> Eigen::VectorXd {
        throw std::invalid_argument("the basis cannot be resolved");
      });
  EXPECT_EQ(failing.folds, 0);
  EXPECT_EQ(failing.why_not, "fold 1 of 6: the basis cannot be resolved");
  const CrossValidation flat = cross_validate(x, Eigen::VectorXd::Constant(6, 2.0), 2, fit_line_and_predict);
  EXPECT_EQ(flat.folds, 0);
  EXPECT_NE(flat.why_not.find("equal"), std::string::npos) << flat.why_not;
}

}  // namespace
}  // namespace rover::study
