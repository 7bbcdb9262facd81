// The record layout: what is encoded is decoded, a record of another layout is
// an error record, never misread.
#include "study/runtime/run_record.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace rover::study {
namespace {

TEST(RunRecord, RoundTripThroughATaskRecord) {
  const RecordLayout layout{2, 3, 4};
  RunRecord r;
  r.status = 0;
  r.message = "";
  r.wall_time_s = 0.25;
  r.rhs_evaluations = 1234;
  r.qoi = {1.5, -2.5};
  for (int k = 0; k < 12; ++k) r.curves.push_back(k * 0.5);
  const RunRecord back = decode_record(layout, encode_record(7, r));
  EXPECT_EQ(back.qoi, r.qoi);
  EXPECT_EQ(back.curves, r.curves);
  EXPECT_EQ(back.wall_time_s, 0.25);
  EXPECT_EQ(back.rhs_evaluations, 1234);
  EXPECT_EQ(back.curve(2, 4)[1], 4.5);  // channel 2, sample 1
  EXPECT_EQ(encode_record(7, r).index, 7);
}

TEST(RunRecord, AnotherLayoutBecomesAnErrorRecord) {
  RunRecord r;
  r.qoi = {1.0};
  const RunRecord back = decode_record({2, 0, 0}, encode_record(0, r));
  EXPECT_EQ(back.status, run_status::kError);
  EXPECT_NE(back.message.find("expected 4"), std::string::npos) << back.message;
  EXPECT_TRUE(std::isnan(back.qoi[0]) && std::isnan(back.qoi[1]));
}

TEST(RunRecord, AFarmFailureWithoutValuesKeepsItsStatusAndMessage) {
  const RunRecord back = decode_record({1, 1, 3}, io::TaskRecord{3, 1, "threw: boom", {}});
  EXPECT_EQ(back.status, 1);
  EXPECT_EQ(back.message, "threw: boom");
  EXPECT_EQ(back.curves.size(), 3u);
}

}  // namespace
}  // namespace rover::study
