// Held-out validation (study/surrogate/surrogate_validation.hpp): Q^2 against
// its definition, and undefined where it has no spread to explain.
#include "study/surrogate/surrogate_validation.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

namespace rover::study {
namespace {

TEST(SurrogateValidation, HeldOutQ2IsOneMinusTheRelativeSquaredError) {
  Eigen::VectorXd observed(3), predicted(3);
  observed << 1.0, 2.0, 3.0;  // spread: sum (y - 2)^2 = 2
  predicted << 1.0, 2.5, 3.0;  // squared error 0.25
  SurrogateValidation v;
  score_held_out(observed, predicted, &v);
  EXPECT_DOUBLE_EQ(v.q2_test, 1.0 - 0.25 / 2.0);
  EXPECT_DOUBLE_EQ(v.rmse_test, std::sqrt(0.25 / 3.0));
  EXPECT_EQ(held_out_q2_undefined_reason(v), "");
}

TEST(SurrogateValidation, OneHeldOutRunOrEqualValuesLeaveQ2Undefined) {
  SurrogateValidation one;
  one.q2_loo = 0.99;
  score_held_out(Eigen::VectorXd::Constant(1, 2.0), Eigen::VectorXd::Constant(1, 2.1), &one);
  EXPECT_TRUE(std::isnan(one.q2_test));
  EXPECT_NEAR(one.rmse_test, 0.1, 1e-12);
  EXPECT_NE(held_out_q2_undefined_reason(one).find("at least 2 held-out runs, got 1"), std::string::npos);
  flag_low_q2("y", 10, 0.95, &one);
  EXPECT_TRUE(one.warning.empty()) << one.warning;  // an undefined Q2 is not a low one
  SurrogateValidation equal;
  score_held_out(Eigen::VectorXd::Constant(4, 2.0), Eigen::VectorXd::Constant(4, 2.0 + 1e-17), &equal);
  EXPECT_TRUE(std::isnan(equal.q2_test));
  EXPECT_NE(held_out_q2_undefined_reason(equal).find("are equal"), std::string::npos);
}

}  // namespace
}  // namespace rover::study
