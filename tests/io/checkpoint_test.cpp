// Tests of io/checkpoint: records survive a round trip through the file, the
// write cadence follows the policy, a checkpoint of another configuration is
// refused, and a crash mid-write leaves the previous checkpoint usable.
#include "io/checkpoint.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "io/hdf5_file.hpp"
#include "test_support.hpp"

namespace rover::io {
namespace {

namespace fs = std::filesystem;

std::vector<TaskRecord> sample_records() {
  return {
      {4, 0, "", {1.5, -2.25, 1.0 / 3.0}},
      {0, 0, "", {}},  // a run with no values
      {9, 2, "wheel 2 lost contact at t = 3.1 s", {}},
      {7, 0, "", {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7}},
  };
}

void expect_same(const std::vector<TaskRecord>& a, const std::vector<TaskRecord>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].index, b[i].index);
    EXPECT_EQ(a[i].status, b[i].status);
    EXPECT_EQ(a[i].message, b[i].message);
    EXPECT_EQ(a[i].values, b[i].values);
  }
}

TEST(ResultCheckpoint, RecordsRoundTripSortedByIndex) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  ResultCheckpoint writer(results, "abc");
  EXPECT_TRUE(writer.load().empty());  // no checkpoint yet
  for (const TaskRecord& record : sample_records()) writer.add(record);
  writer.save();
  EXPECT_EQ(writer.path(), results + ".checkpoint");

  ResultCheckpoint reader(results, "abc");
  std::vector<TaskRecord> expected = sample_records();
  std::sort(expected.begin(), expected.end(),
            [](const TaskRecord& x, const TaskRecord& y) { return x.index < y.index; });
  expect_same(reader.load(), expected);
  EXPECT_EQ(missing_indices(11, reader.load()), (std::vector<int>{1, 2, 3, 5, 6, 8, 10}));
}

TEST(ResultCheckpoint, ResumedCheckpointKeepsOldRecords) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  {
    ResultCheckpoint first(results, "abc");
    first.add({1, 0, "", {1.0}});
    first.save();
  }
  ResultCheckpoint second(results, "abc");
  ASSERT_EQ(second.load().size(), 1u);
  second.add({2, 0, "", {2.0}});
  second.save();
  ResultCheckpoint third(results, "abc");
  expect_same(third.load(), {{1, 0, "", {1.0}}, {2, 0, "", {2.0}}});
}

TEST(ResultCheckpoint, WritesEveryKRecordsOrTSeconds) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  ResultCheckpoint by_count(results, "abc", {.every_records = 3, .every_seconds = 1e9});
  by_count.add({0, 0, "", {0.0}});
  by_count.add({1, 0, "", {1.0}});
  EXPECT_FALSE(fs::exists(by_count.path()));
  by_count.add({2, 0, "", {2.0}});
  EXPECT_TRUE(fs::exists(by_count.path()));
  EXPECT_EQ(ResultCheckpoint(results, "abc").load().size(), 3u);

  const std::string timed = testing::temp_dir() + "/timed.h5";
  ResultCheckpoint by_time(timed, "abc", {.every_records = 1000, .every_seconds = 0.0});
  by_time.add({0, 0, "", {0.0}});
  EXPECT_TRUE(fs::exists(by_time.path()));
}

TEST(ResultCheckpoint, DifferentFingerprintIsRefused) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  const std::string old_config = config_fingerprint(R"({"runs": 1000, "seed": 1})");
  const std::string new_config = config_fingerprint(R"({"runs": 1000, "seed": 2})");
  ResultCheckpoint old_study(results, old_config);
  old_study.add({0, 0, "", {1.0}});
  old_study.save();
  try {
    ResultCheckpoint(results, new_config).load();
    FAIL() << "a checkpoint of another configuration was accepted";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(results + ".checkpoint"), std::string::npos) << message;
    EXPECT_NE(message.find(old_config), std::string::npos) << message;
    EXPECT_NE(message.find(new_config), std::string::npos) << message;
  }
}

TEST(ResultCheckpoint, CrashDuringWriteLeavesThePreviousCheckpoint) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  ResultCheckpoint study(results, "abc");
  study.add({0, 0, "", {1.0}});
  study.save();
  EXPECT_FALSE(fs::exists(study.path() + ".partial"));
  // A crash in the middle of the next write leaves a half-written temp file.
  std::ofstream(study.path() + ".partial") << "half an HDF5 file";
  expect_same(ResultCheckpoint(results, "abc").load(), {{0, 0, "", {1.0}}});
  // The next write replaces it.
  study.add({1, 0, "", {2.0}});
  study.save();
  EXPECT_FALSE(fs::exists(study.path() + ".partial"));
  EXPECT_EQ(ResultCheckpoint(results, "abc").load().size(), 2u);
  study.remove();
  EXPECT_FALSE(fs::exists(study.path()));
}

TEST(ResultCheckpoint, OtherHdf5FileIsNotACheckpoint) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  Hdf5Writer other(ResultCheckpoint::path_for(results));
  other.write("/index", std::vector<int>{1});
  other.commit();
  EXPECT_THROW(ResultCheckpoint(results, "abc").load(), std::runtime_error);
}

TEST(ConfigFingerprint, IsFnv1aOfTheText) {
  // Published FNV-1a 64-bit test vectors.
  EXPECT_EQ(config_fingerprint(""), "cbf29ce484222325");
  EXPECT_EQ(config_fingerprint("a"), "af63dc4c8601ec8c");
  EXPECT_EQ(config_fingerprint("foobar"), "85944171f73967e8");
  EXPECT_NE(config_fingerprint("{\"seed\": 1}"), config_fingerprint("{\"seed\": 2}"));
}

}  // namespace
}  // namespace rover::io
