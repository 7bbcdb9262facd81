// The share of a compared curve's time span inside the times compared
// (core/curve_overlap.hpp): a drop recorded at 20 kHz with times in
// milliseconds against the 0.3 s run it was made from, and records longer
// than the run that are no unit mistake.
#include "core/curve_overlap.hpp"

#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace rover {
namespace {

TEST(CurveOverlap, ShareOfTheSpanInsideTheInterval) {
  EXPECT_DOUBLE_EQ(span_share_within(0.0, 300.0, 0.0, 0.3), 0.001);
  EXPECT_DOUBLE_EQ(span_share_within(0.0, 1.0, 0.25, 0.5), 0.25);
  EXPECT_DOUBLE_EQ(span_share_within(0.0, 1.0, -1.0, 2.0), 1.0);
  EXPECT_DOUBLE_EQ(span_share_within(2.0, 3.0, 0.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(span_share_within(0.5, 0.5, 0.0, 1.0), 1.0);  // one instant, inside
  EXPECT_DOUBLE_EQ(span_share_within(1.5, 1.5, 0.0, 1.0), 0.0);
}

TEST(CurveOverlap, ACurveInMillisecondsIsRefusedWithAHint) {
  // 6000 samples at 20 kHz, t in ms: 0 .. 299.95; the run covers 0 .. 0.3.
  const std::string p = curve_share_problem(0.0, 299.95, 0.0, 0.3);
  EXPECT_NE(p.find("only 0.1 % of its time span"), std::string::npos) << p;
  EXPECT_NE(p.find("t runs to 299.95, milliseconds?"), std::string::npos) << p;
  EXPECT_NE(p.find("less than the 2 %"), std::string::npos) << p;
  // The same record in seconds, and records 10 and 50 times longer than the run.
  EXPECT_EQ(curve_share_problem(0.0, 0.29995, 0.0, 0.3), "");
  EXPECT_EQ(curve_share_problem(0.0, 3.0, 0.0, 0.3), "");
  EXPECT_EQ(curve_share_problem(0.0, 15.0, 0.0, 0.3), "");
  EXPECT_NE(curve_share_problem(0.0, 16.0, 0.0, 0.3), "");
}

TEST(CurveOverlap, TheMillisecondsHintOnlyBeyondTheShareRule) {
  EXPECT_EQ(milliseconds_hint(299.95, 0.5), ": t runs to 299.95, milliseconds?");
  EXPECT_EQ(milliseconds_hint(1.2, 1.0), "");  // data a little past a run: no unit mistake
  EXPECT_EQ(milliseconds_hint(300.0, 0.0), "");
}


// Two curves' times agree to rounding within a thousandth of the finer
// sampling step: 0.28 s and 0.28 - 0.02 + 0.02 are one time; a time farther
// beyond the common span is outside it.
TEST(CurveOverlap, TimesWithinTheCommonSpanToRounding) {
  const std::vector<double> a{0.0, 0.1, 0.2, 0.3};
  std::vector<double> b{0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3};
  for (double& t : b) t -= 0.02;
  const CommonSpan span = common_span(a, b);
  EXPECT_DOUBLE_EQ(span.first_s, 0.0);
  EXPECT_DOUBLE_EQ(span.last_s, 0.3 - 0.02);
  const double tolerance = sample_time_tolerance_s(a, b);
  EXPECT_DOUBLE_EQ(tolerance, 1e-3 * 0.05);
  EXPECT_EQ(time_in_span(0.28, span, tolerance), span.last_s);  // 0.27999999999999997 on B's clock
  EXPECT_EQ(time_in_span(0.1, span, tolerance), 0.1);
  EXPECT_EQ(time_in_span(0.29, span, tolerance), std::nullopt);
  EXPECT_EQ(time_in_span(-0.001, span, tolerance), std::nullopt);
  EXPECT_EQ(time_in_span(1.0, span, tolerance), std::nullopt);
}

}  // namespace
}  // namespace rover
