// Tests of io/checkpoint: records survive a round trip through the file, the
// file is append-only (a resumed study continues it, old bytes are never
// rewritten, the bytes written per record do not grow with the number of
// records), a torn last record costs only that record, the write cadence
// follows the policy, and checkpoints of another configuration or format are
// refused with a message that says why.
#include "io/checkpoint.hpp"

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "io/hdf5_file.hpp"
#include "test_support.hpp"

namespace rover::io {
namespace {

namespace fs = std::filesystem;

// Sizes from the format in checkpoint.hpp: a header of 20 bytes plus the
// fingerprint, a record of 24 bytes plus its message and 8 bytes per value.
std::size_t header_bytes(const std::string& fingerprint) { return 20 + fingerprint.size(); }
std::size_t record_bytes(const TaskRecord& r) { return 24 + r.message.size() + 8 * r.values.size(); }

std::vector<TaskRecord> sample_records() {
  return {
      {4, 0, "", {1.5, -2.25, 1.0 / 3.0}},
      {0, 0, "", {}},  // a run with no values
      {9, 2, "wheel 2 lost contact at t = 3.1 s", {}},
      {7, 0, "", {0.1, -0.0, 5e-324, 1e300, std::numeric_limits<double>::infinity(), 0.6, 0.7}},
  };
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void expect_same(const std::vector<TaskRecord>& a, const std::vector<TaskRecord>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].index, b[i].index);
    EXPECT_EQ(a[i].status, b[i].status);
    EXPECT_EQ(a[i].message, b[i].message);
    ASSERT_EQ(a[i].values.size(), b[i].values.size());
    for (std::size_t k = 0; k < a[i].values.size(); ++k) {
      EXPECT_EQ(a[i].values[k], b[i].values[k]);
      EXPECT_EQ(std::signbit(a[i].values[k]), std::signbit(b[i].values[k]));
    }
  }
}

// Expects `call` to throw a std::runtime_error whose message contains every one of `parts`.
template <typename Call>
void expect_error_naming(Call call, const std::vector<std::string>& parts) {
  try {
    call();
    ADD_FAILURE() << "no exception thrown";
  } catch (const std::runtime_error& e) {
    for (const std::string& part : parts)
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "message '" << e.what() << "' does not name '" << part << "'";
  }
}

TEST(ResultCheckpoint, RecordsRoundTripSortedByIndex) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  ResultCheckpoint writer(results, "abc");
  EXPECT_TRUE(writer.load().empty());  // no checkpoint yet
  for (const TaskRecord& record : sample_records()) writer.add(record);
  writer.save();
  EXPECT_EQ(writer.path(), results + ".checkpoint");
  EXPECT_EQ(writer.size(), 4u);
  EXPECT_TRUE(writer.contains(9));
  EXPECT_FALSE(writer.contains(5));
  std::size_t expected_size = header_bytes("abc");
  for (const TaskRecord& record : sample_records()) expected_size += record_bytes(record);
  EXPECT_EQ(fs::file_size(writer.path()), expected_size);

  ResultCheckpoint reader(results, "abc");
  std::vector<TaskRecord> expected = sample_records();
  std::sort(expected.begin(), expected.end(),
            [](const TaskRecord& x, const TaskRecord& y) { return x.index < y.index; });
  expect_same(reader.load(), expected);
  EXPECT_EQ(reader.size(), 4u);
  EXPECT_EQ(reader.torn_tail_bytes(), 0u);
  EXPECT_EQ(missing_indices(11, reader.load()), (std::vector<int>{1, 2, 3, 5, 6, 8, 10}));
}

TEST(ResultCheckpoint, AppendAfterLoadContinuesTheFile) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  {
    ResultCheckpoint first(results, "abc");
    first.add({1, 0, "", {1.0}});
    first.save();
  }
  const std::string before = file_bytes(ResultCheckpoint::path_for(results));
  ResultCheckpoint second(results, "abc");
  ASSERT_EQ(second.load().size(), 1u);
  second.add({2, 0, "", {2.0}});
  second.add({1, 3, "rerun", {}});  // a second record of task 1 replaces the first
  second.save();
  EXPECT_EQ(second.bytes_written(), record_bytes({2, 0, "", {2.0}}) + record_bytes({1, 3, "rerun", {}}));
  const std::string after = file_bytes(second.path());
  EXPECT_EQ(after.substr(0, before.size()), before);  // old bytes untouched
  EXPECT_EQ(after.size(), before.size() + second.bytes_written());
  ResultCheckpoint third(results, "abc");
  expect_same(third.load(), {{1, 3, "rerun", {}}, {2, 0, "", {2.0}}});
  EXPECT_EQ(third.size(), 2u);
}

TEST(ResultCheckpoint, WriteCostDoesNotGrowWithTheNumberOfRecords) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  ResultCheckpoint study(results, "abc", {.every_records = 1, .every_seconds = 1e9});
  const TaskRecord typical{0, 0, "", std::vector<double>(20, 0.25)};
  std::vector<std::uint64_t> cost;  // bytes written by each add()
  std::string first_kilobyte;
  for (int i = 0; i < 3000; ++i) {
    const std::uint64_t before = study.bytes_written();
    study.add({i, 0, "", typical.values});
    cost.push_back(study.bytes_written() - before);
    if (i == 5) first_kilobyte = file_bytes(study.path()).substr(0, 1000);
  }
  const std::uint64_t record = record_bytes(typical);
  EXPECT_EQ(cost[0], header_bytes("abc") + record);  // creates the file
  for (std::size_t i = 1; i < cost.size(); ++i) ASSERT_EQ(cost[i], record) << "record " << i;
  EXPECT_EQ(fs::file_size(study.path()), header_bytes("abc") + 3000 * record);
  EXPECT_EQ(file_bytes(study.path()).substr(0, 1000), first_kilobyte);
  EXPECT_EQ(ResultCheckpoint(results, "abc").load().size(), 3000u);
}

TEST(ResultCheckpoint, TornTailLosesOnlyTheLastRecord) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  const std::string path = ResultCheckpoint::path_for(results);
  std::vector<TaskRecord> records;
  for (int i = 0; i < 6; ++i) records.push_back({i, 0, "", {0.5 * i, 1.0 * i}});
  {
    ResultCheckpoint study(results, "abc");
    for (const TaskRecord& r : records) study.add(r);
    study.save();
  }
  const std::uintmax_t full = fs::file_size(path);
  const std::size_t record = record_bytes(records[0]);

  // A crash mid-append: the last record lacks its last 3 bytes.
  fs::resize_file(path, full - 3);
  ResultCheckpoint resumed(results, "abc");
  expect_same(resumed.load(), {records.begin(), records.end() - 1});
  EXPECT_EQ(resumed.torn_tail_bytes(), record - 3);
  EXPECT_FALSE(resumed.contains(5));
  // The next append cuts the torn bytes and continues after record 4.
  resumed.add(records[5]);
  resumed.save();
  EXPECT_EQ(fs::file_size(path), full);
  expect_same(ResultCheckpoint(results, "abc").load(), records);

  // A complete but corrupted last record (a flipped bit) fails its checksum.
  std::string bytes = file_bytes(path);
  bytes[bytes.size() - 10] ^= 0x04;
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  ResultCheckpoint flipped(results, "abc");
  expect_same(flipped.load(), {records.begin(), records.end() - 1});
  EXPECT_EQ(flipped.torn_tail_bytes(), record);
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
  by_count.add({3, 0, "", {3.0}});
  EXPECT_EQ(ResultCheckpoint(results, "abc").load().size(), 3u);  // buffered
  by_count.save();
  EXPECT_EQ(ResultCheckpoint(results, "abc").load().size(), 4u);

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
  expect_error_naming([&] { ResultCheckpoint(results, new_config).load(); },
                      {results + ".checkpoint", "different study configuration", "the study file", "--resume"});
}

TEST(ResultCheckpoint, ASettingThatDiffersIsNamedWithBothValues) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  const std::string inputs = config_fingerprint("the study's files");
  const std::string made = add_run_setting(add_run_setting(inputs, {"--samples", "300", false}), {"--seed", "3", false});
  ResultCheckpoint old_study(results, made);
  old_study.add({0, 0, "", {1.0}});
  old_study.save();
  // The same values, whether from the file or a flag: the same runs.
  const std::string same = add_run_setting(add_run_setting(inputs, {"--samples", "300", true}), {"--seed", "3", false});
  EXPECT_TRUE(keys_match(made, same));
  EXPECT_EQ(ResultCheckpoint(results, same).load().size(), 1u);
  const std::string more = add_run_setting(add_run_setting(inputs, {"--samples", "320", true}), {"--seed", "3", false});
  EXPECT_FALSE(keys_match(made, more));
  expect_error_naming([&] { ResultCheckpoint(results, more).load(); },
                      {"--samples 320 here", "made with samples 300 (from the study file, no --samples)"});
  const std::string message = key_mismatch(made, more);
  EXPECT_EQ(message.find("the study file or a file it names"), std::string::npos) << message;
  // Inputs added to the key keep its settings.
  EXPECT_NE(extend_key_digest(made, "candidates").find("--samples\t300"), std::string::npos);
  // An earlier checkpoint, written before keys held settings, is refused as such.
  EXPECT_NE(key_mismatch(config_fingerprint("old"), more).find("earlier version of rover"), std::string::npos);
}

TEST(ResultCheckpoint, ASettingOfAnotherInputFileNamesThatFile) {
  // rover evaluate has no study file: its integrator, unless --integrator
  // gives one, is the scenario's.
  const std::string inputs = config_fingerprint("a design and its scenario");
  const std::string made = add_run_setting(inputs, {"--integrator", "integrator", false, "the scenario"});
  const std::string now = add_run_setting(inputs, {"--integrator", "dopri5", true});
  EXPECT_FALSE(keys_match(made, now));
  const std::string message = key_mismatch(made, now);
  EXPECT_NE(message.find("--integrator dopri5 here, but the checkpoint's runs were made with the scenario's "
                         "integrator (no --integrator)"),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find("study file"), std::string::npos) << message;
  EXPECT_TRUE(keys_match(made, add_run_setting(inputs, {"--integrator", "integrator", false, "the scenario"})));
}

TEST(ResultCheckpoint, FilesOfAnotherFormatAreRefused) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  const std::string path = ResultCheckpoint::path_for(results);
  {  // the HDF5 checkpoint of earlier versions
    Hdf5Writer other(path);
    other.write("/index", std::vector<int>{1});
    other.attribute("/", "format", "rover-checkpoint-1");
    other.commit();
  }
  expect_error_naming([&] { ResultCheckpoint(results, "abc").load(); }, {path, "HDF5"});
  std::ofstream(path, std::ios::trunc) << "index,status\n1,0\n";
  expect_error_naming([&] { ResultCheckpoint(results, "abc").load(); },
                      {path, "not a rover checkpoint"});
  {
    ResultCheckpoint study(results, "abc");
    study.add({0, 0, "", {}});
    study.save();
  }
  std::string bytes = file_bytes(path);
  bytes[8] = 3;  // format version 3
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  expect_error_naming([&] { ResultCheckpoint(results, "abc").load(); }, {path, "version 3"});
  bytes[8] = 2;
  bytes[17] = 'x';  // the fingerprint "abc" -> "axc" without its checksum
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  expect_error_naming([&] { ResultCheckpoint(results, "abc").load(); }, {path, "damaged"});
}

TEST(ResultCheckpoint, RemoveDeletesTheFileAndStartsAfresh) {
  const std::string results = testing::temp_dir() + "/mc.h5";
  ResultCheckpoint study(results, "abc");
  study.add({0, 0, "", {1.0}});
  study.save();
  EXPECT_FALSE(fs::exists(study.path() + ".partial"));
  study.remove();
  EXPECT_FALSE(fs::exists(study.path()));
  EXPECT_EQ(study.size(), 0u);
  study.add({1, 0, "", {2.0}});
  study.save();
  expect_same(ResultCheckpoint(results, "abc").load(), {{1, 0, "", {2.0}}});
  // Without load(), a new study replaces an old file.
  ResultCheckpoint fresh(results, "abc");
  fresh.add({2, 0, "", {}});
  fresh.save();
  expect_same(ResultCheckpoint(results, "abc").load(), {{2, 0, "", {}}});
  EXPECT_THROW(fresh.add({-1, 0, "", {}}), std::invalid_argument);
}

TEST(ResultCheckpoint, FullDiskIsAClearErrorAndKeepsWhatWasWritten) {
  // In a child process limited to 4 KB files (a full disk without root).
  const std::string results = testing::temp_dir() + "/mc.h5";
  const std::string path = ResultCheckpoint::path_for(results);
  std::fflush(nullptr);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const rlimit limit{4096, 4096};
    setrlimit(RLIMIT_FSIZE, &limit);
    std::signal(SIGXFSZ, SIG_IGN);
    ResultCheckpoint study(results, "abc", {.every_records = 10, .every_seconds = 1e9});
    try {
      for (int i = 0; i < 1000; ++i) study.add({i, 0, "", std::vector<double>(5, 1.0)});
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      const bool clear = message.find(path) != std::string::npos &&
                         message.find("disk is full") != std::string::npos;
      std::_Exit(clear ? 0 : 2);
    }
    std::_Exit(1);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status)) << "the child died of signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: no error thrown; 2: the message is not clear";
  // The write stopped at the limit: every whole record before it is kept, the
  // torn one at the limit is dropped.
  ResultCheckpoint resumed(results, "abc");
  const std::vector<TaskRecord> kept = resumed.load();
  const std::size_t record = 24 + 8 * 5, room = 4096 - header_bytes("abc");
  EXPECT_EQ(fs::file_size(path), 4096u);
  EXPECT_EQ(kept.size(), room / record);
  EXPECT_EQ(resumed.torn_tail_bytes(), room % record);
  for (std::size_t i = 0; i < kept.size(); ++i) EXPECT_EQ(kept[i].index, static_cast<int>(i));
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
