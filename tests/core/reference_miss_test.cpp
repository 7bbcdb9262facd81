// The reference-miss test (core/reference_miss.hpp): a curve off by more than
// the reference's own span, as a reference in millimetres is, against the
// shipped synthetic drop (heights in metres).
#include "core/reference_miss.hpp"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/metrics.hpp"
#include "io/csv.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

TEST(ReferenceMiss, SpanIgnoresNonFiniteValues) {
  EXPECT_EQ(value_span({0.25, std::nan(""), 0.2, 0.3, INFINITY}), 0.3 - 0.2);
  EXPECT_EQ(value_span({}), 0.0);
}

TEST(ReferenceMiss, MillimetresMissTheMetreCurveByMoreThanItsSpan) {
  const io::MeasuredCurve m =
      io::read_measured_curve(testing::source_path("configs/data/drop_horizontal_synthetic.csv"));
  std::vector<double> mm = m.z_m, offset = m.z_m;
  for (double& z : mm) z *= 1000.0;
  for (double& z : offset) z += 0.001;  // a 1 mm error: a plausible model
  const double span = value_span(m.z_m);
  EXPECT_TRUE(every_rms_exceeds_span({rms_difference(m.t_s, mm, m.t_s, m.z_m)}, span));
  EXPECT_FALSE(every_rms_exceeds_span({rms_difference(m.t_s, offset, m.t_s, m.z_m)}, span));
}

TEST(ReferenceMiss, EveryFiniteRmsMustExceedTheSpan) {
  EXPECT_TRUE(every_rms_exceeds_span({2.0, std::nan(""), 3.0}, 1.0));
  EXPECT_FALSE(every_rms_exceeds_span({2.0, 0.5}, 1.0));
  EXPECT_FALSE(every_rms_exceeds_span({std::nan("")}, 1.0));  // no finite run: nothing to judge
  const std::string text = reference_missed_text("every run misses", "r.csv", 0.05, "m", "channel named");
  EXPECT_NE(text.find("every run misses the reference r.csv by more than the 0.05 m its values span"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("millimetres"), std::string::npos);
}

}  // namespace
}  // namespace rover
