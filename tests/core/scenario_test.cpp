// Scenario helpers (core/scenario.cpp): the output grid of MODEL.md section 8
// must end at duration_s even where duration / period rounds just below an
// integer in floating point (0.7 s at 1 kHz: 699.9999999999999 periods).
#include "core/scenario.hpp"

#include <gtest/gtest.h>

namespace rover {
namespace {

Scenario scenario_of(double duration_s, double output_rate_hz) {
  Scenario s;
  s.duration_s = duration_s;
  s.output_rate_hz = output_rate_hz;
  return s;
}

TEST(Scenario, OutputSamplesRunFromZeroToTheDuration) {
  EXPECT_EQ(output_sample_count(scenario_of(1.0, 1000.0)), 1001u);
  EXPECT_EQ(output_sample_count(scenario_of(0.7, 1000.0)), 701u);
  EXPECT_EQ(output_sample_count(scenario_of(2.3, 300.0)), 691u);
  EXPECT_EQ(output_sample_count(scenario_of(0.25, 1000.0)), 251u);
}

TEST(Scenario, AnOutputGridThatDoesNotReachTheDurationStopsBeforeIt) {
  // 1 s at 3 Hz: samples at 0, 1/3, 2/3 and 1 s; at 0.9 s the last is 2/3.
  EXPECT_EQ(output_sample_count(scenario_of(1.0, 3.0)), 4u);
  EXPECT_EQ(output_sample_count(scenario_of(0.9, 3.0)), 3u);
}

}  // namespace
}  // namespace rover
