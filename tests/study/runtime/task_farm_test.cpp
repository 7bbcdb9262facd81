// Tests of study/runtime/task_farm in one process (no MPI initialised: the plain-loop
// path). The MPI paths (1 and 3 ranks, identical outputs) are tested by
// tests/study/runtime/task_farm_probe.cpp under mpiexec (see tests/CMakeLists.txt).
#include "study/runtime/task_farm.hpp"

#include "study/estimators/work_stopped.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

namespace rover::study {
namespace {

TaskResult square_root_run(int index) {
  if (index == 3) throw std::runtime_error("terrain sample 3 is not walkable");
  return {index, 0, "", {std::sqrt(static_cast<double>(index)), static_cast<double>(index)}};
}

TEST(TaskFarm, RunsEachTaskOnceAndSortsResults) {
  const std::vector<int> tasks = {9, 3, 0, 7, 4};  // e.g. the missing ones on --resume
  std::multiset<int> computed, reported;
  std::ostringstream progress;
  const std::vector<TaskResult> results = run_task_farm(
      tasks,
      [&](int i) {
        computed.insert(i);
        return square_root_run(i);
      },
      [&](const TaskResult& r) { reported.insert(r.index); },
      {.progress_interval_s = 5, .label = "sweep", .progress = &progress});

  EXPECT_EQ(computed, std::multiset<int>(tasks.begin(), tasks.end()));
  EXPECT_EQ(reported, computed);
  ASSERT_EQ(results.size(), tasks.size());
  const std::vector<int> sorted = {0, 3, 4, 7, 9};
  for (std::size_t k = 0; k < results.size(); ++k) {
    const TaskResult& r = results[k];
    EXPECT_EQ(r.index, sorted[k]);
    if (r.index == 3) {
      EXPECT_NE(r.status, 0);
      EXPECT_EQ(r.message, "terrain sample 3 is not walkable");
      EXPECT_TRUE(r.values.empty());
    } else {
      EXPECT_EQ(r.status, 0);
      EXPECT_EQ(r.values, square_root_run(r.index).values);
    }
  }
  EXPECT_NE(progress.str().find("sweep: 5/5 done (1 failed)"), std::string::npos) << progress.str();
}

TEST(TaskFarm, IndexIsTheTasksWhateverComputeReturns) {
  const auto results =
      run_task_farm({5}, [](int) { return TaskResult{}; }, nullptr, {.progress = nullptr});
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].index, 5);
}

// A task that a stop request ends midway (compute throws WorkStopped) is not
// done: no result and no failure; the tasks before it stand, none follows.
TEST(TaskFarm, ATaskStoppedMidwayIsNotDone) {
  std::atomic<bool> stop{false};
  std::vector<int> computed;
  const auto compute = [&](int i) {
    computed.push_back(i);
    if (i == 2) {
      stop = true;  // the signal arrives during task 2
      stop_if_requested(&stop, "task 2");
    }
    return TaskResult{i, 0, "", {static_cast<double>(i)}};
  };
  std::ostringstream progress;
  const std::vector<TaskResult> results =
      run_task_farm({0, 1, 2, 3, 4}, compute, nullptr, {.label = "sweep", .progress = &progress, .stop = &stop});
  EXPECT_EQ(computed, (std::vector<int>{0, 1, 2}));
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].index, 0);
  EXPECT_EQ(results[1].index, 1);
  EXPECT_NE(progress.str().find("sweep: 2/5 done (0 failed)"), std::string::npos) << progress.str();
}

TEST(TaskFarm, InvalidTaskListsAreRefused) {
  const auto compute = [](int i) { return TaskResult{i, 0, "", {}}; };
  EXPECT_THROW(run_task_farm({1, 2, 1}, compute, nullptr, {.progress = nullptr}),
               std::invalid_argument);
  EXPECT_THROW(run_task_farm({-1}, compute, nullptr, {.progress = nullptr}), std::invalid_argument);
  EXPECT_TRUE(run_task_farm({}, compute, nullptr, {.progress = nullptr}).empty());
}

TEST(TaskFarm, ProgressLineReportsRateAndEta) {
  // 123 runs in 30 s: 4.1 runs/s; 877 left take 213.9 s.
  EXPECT_EQ(progress_line("mc", 123, 1000, 2, 30.0),
            "mc: 123/1000 done (2 failed), 4.1 runs/s, ETA 3m34s");
  EXPECT_EQ(progress_line("mc", 0, 10, 0, 3.0), "mc: 0/10 done (0 failed), 0.00 runs/s, ETA ?");
  EXPECT_EQ(progress_line("mc", 10, 10, 0, 2.0), "mc: 10/10 done (0 failed), 5.0 runs/s");
  EXPECT_EQ(progress_line("mc", 1, 10000, 0, 2.0),
            "mc: 1/10000 done (0 failed), 0.50 runs/s, ETA 5h33m");
}

}  // namespace
}  // namespace rover::study
