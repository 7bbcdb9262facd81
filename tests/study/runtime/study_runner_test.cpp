// Checkpoint and resume of the study runner (study/runtime/study_runner.cpp),
// single process, and the interrupt guard's handling of repeated signals.
#include "study/runtime/study_runner.hpp"

#include <chrono>
#include <csignal>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "io/checkpoint.hpp"
#include "test_support.hpp"

namespace rover::study {
namespace {

TEST(StudyRunner, ResumeComputesOnlyWhatIsMissing) {
  const std::string results = rover::testing::temp_dir() + "/study.h5";
  // An interrupted study: 3 of 8 runs in the checkpoint.
  {
    io::ResultCheckpoint checkpoint(results, "fp-1");
    for (int i : {0, 4, 7}) checkpoint.add({i, 0, "", {10.0 * i}});
    checkpoint.save();
  }
  std::vector<int> computed;
  auto compute = [&](int i) {
    computed.push_back(i);
    return TaskResult{i, 0, "", {10.0 * i}};
  };
  StudyRunOptions options;
  options.results_path = results;
  options.fingerprint = "fp-1";
  options.resume = true;
  options.label = "test";
  options.progress_interval_s = 0;
  const auto all = run_study_tasks(8, compute, options);
  EXPECT_EQ(computed, (std::vector<int>{1, 2, 3, 5, 6}));
  ASSERT_EQ(all.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(all[i].index, i);
    EXPECT_EQ(all[i].values, std::vector<double>{10.0 * i});
  }
  // A second resume has nothing left to do.
  computed.clear();
  run_study_tasks(8, compute, options);
  EXPECT_TRUE(computed.empty());
  remove_checkpoint(results);
  EXPECT_FALSE(std::filesystem::exists(io::ResultCheckpoint::path_for(results)));
}

TEST(StudyRunner, ResumeRefusesACheckpointOfAnotherConfiguration) {
  const std::string results = rover::testing::temp_dir() + "/study.h5";
  {
    io::ResultCheckpoint checkpoint(results, "fp-old");
    checkpoint.add({0, 0, "", {1.0}});
    checkpoint.save();
  }
  StudyRunOptions options;
  options.results_path = results;
  options.fingerprint = "fp-new";
  options.resume = true;
  options.label = "test";
  options.progress_interval_s = 0;
  EXPECT_THROW(run_study_tasks(2, [](int i) { return TaskResult{i, 0, "", {}}; }, options),
               std::runtime_error);
}

TEST(StudyRunner, WithoutResumeEverythingIsComputedAgain) {
  const std::string results = rover::testing::temp_dir() + "/study.h5";
  {
    io::ResultCheckpoint checkpoint(results, "fp");
    checkpoint.add({0, 0, "", {1.0}});
    checkpoint.save();
  }
  int calls = 0;
  StudyRunOptions options;
  options.results_path = results;
  options.fingerprint = "fp";
  options.resume = false;
  options.label = "test";
  options.progress_interval_s = 0;
  run_study_tasks(3, [&](int i) { ++calls; return TaskResult{i, 0, "", {}}; }, options);
  EXPECT_EQ(calls, 3);
}

// `timeout` and batch systems send one stop request to the process and to its
// group: the same signal twice at once is one request, not a kill.
TEST(InterruptGuard, ASignalRepeatedAtOnceIsOneRequestToStop) {
  EXPECT_EXIT(
      {
        const InterruptGuard guard;
        std::raise(SIGTERM);
        std::raise(SIGTERM);
        std::exit(InterruptGuard::flag().load() ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
}

// A user who signals again after the window means it: the process dies of
// the signal as it would without the guard.
TEST(InterruptGuard, ASecondSignalAfterTheWindowKills) {
  EXPECT_EXIT(
      {
        const InterruptGuard guard;
        std::raise(SIGINT);
        std::this_thread::sleep_for(
            std::chrono::duration<double>(1.2 * InterruptGuard::kSignalRepeatWindow_s));
        std::raise(SIGINT);
        std::exit(0);
      },
      ::testing::KilledBySignal(SIGINT), "");
}

// A closed terminal (SIGHUP) is a request to stop like SIGTERM, named in
// the messages; a closed output pipe (SIGPIPE, raised again by every later
// write) is one too, and never kills, however late it repeats.
TEST(InterruptGuard, HangupAndAClosedPipeAreRequestsToStop) {
  EXPECT_EXIT(
      {
        const InterruptGuard guard;
        std::raise(SIGHUP);
        std::exit(InterruptGuard::flag().load() && InterruptGuard::signal_name() == "SIGHUP" ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
  EXPECT_EXIT(
      {
        const InterruptGuard guard;
        std::raise(SIGPIPE);
        std::this_thread::sleep_for(
            std::chrono::duration<double>(1.2 * InterruptGuard::kSignalRepeatWindow_s));
        std::raise(SIGPIPE);
        std::exit(InterruptGuard::flag().load() && InterruptGuard::signal_name().starts_with("SIGPIPE") ? 0 : 1);
      },
      ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace rover::study
