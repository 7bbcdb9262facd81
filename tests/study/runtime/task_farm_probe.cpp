// MPI test program for study/runtime/task_farm, run by CTest under
// `mpiexec -np 1` and `-np 3`, and without mpiexec (see tests/CMakeLists.txt).
//
//   task_farm_probe <output prefix>
//
// Runs 60 tasks of uneven cost (every 10th one 40 ms, the others 2 ms; task 13
// throws) and checks on rank 0: every task computed exactly once over all
// ranks, results sorted with the values compute() returned, the throwing task
// recorded as failed, on_result called once per task on the main thread, the
// checkpoint written from on_result holds the same records, work reached more
// than one rank (rank 0's CPU time is printed, for information). Then it
// checks that an exception in on_result and an invalid task list come out of
// rank 0 while the workers return. Writes <prefix>.h5 from the results, which
// must be identical byte for byte whatever the number of ranks. Exit status 0
// if every check passed.
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

// The C API only: study/CMakeLists.txt defines OMPI_SKIP_MPICXX and
// MPICH_SKIP_MPICXX for every user of rover_study.
#include <mpi.h>

#include "io/checkpoint.hpp"
#include "io/hdf5_file.hpp"
#include "study/runtime/task_farm.hpp"

namespace {

using rover::study::TaskResult;

constexpr int kTasks = 60;
constexpr int kFailingTask = 13;

// The values of task i: a record whose length depends on i (0 to 3 values).
std::vector<double> expected_values(int i) {
  std::vector<double> values;
  for (int k = 0; k < i % 4; ++k) values.push_back(std::sin(0.1 * i + k) / (1.0 + k));
  return values;
}

TaskResult compute(int i) {
  std::this_thread::sleep_for(std::chrono::milliseconds(i % 10 == 0 ? 40 : 2));
  if (i == kFailingTask) throw std::runtime_error("task 13 fails on purpose");
  return {i, 0, "", expected_values(i)};
}

double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

int failures = 0;
void check(bool ok, const std::string& what) {
  if (!ok) {
    ++failures;
    std::cerr << "task_farm_probe: FAILED: " << what << std::endl;
  }
}

}  // namespace

// MPI as study::MpiSession sets it up (MPI_THREAD_SERIALIZED). Written out here
// because librover_study's mpi_session.o is compiled with Open MPI's C++
// bindings, which this program would then have to link.
class Mpi {
 public:
  Mpi(int* argc, char*** argv) {
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~Mpi() { MPI_Finalize(); }
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
};

int run(const Mpi& mpi, const std::string& prefix);

int main(int argc, char** argv) {
  const Mpi mpi(&argc, &argv);
  if (argc != 2) {
    if (mpi.rank() == 0) std::cerr << "usage: task_farm_probe <output prefix>\n";
    return 2;
  }
  try {
    return run(mpi, argv[1]);
  } catch (const std::exception& e) {
    std::cerr << "task_farm_probe: rank " << mpi.rank() << ": " << e.what() << std::endl;
    MPI_Abort(MPI_COMM_WORLD, 1);
    return 1;
  }
}

int run(const Mpi& mpi, const std::string& prefix) {
  const bool root = mpi.rank() == 0;
  if (root) std::filesystem::create_directories(std::filesystem::path(prefix).parent_path());

  // --- the main run: all tasks, checkpointed from on_result
  std::vector<int> tasks(kTasks);
  for (int i = 0; i < kTasks; ++i) tasks[static_cast<std::size_t>(i)] = i;
  const std::string checkpoint_target = prefix + ".h5";
  if (root) std::filesystem::remove(rover::io::ResultCheckpoint::path_for(checkpoint_target));
  rover::io::ResultCheckpoint checkpoint(checkpoint_target, "probe",
                                         {.every_records = 7, .every_seconds = 60.0});
  int computed_here = 0;
  std::multiset<int> reported;
  bool reported_on_main_thread = true;
  const std::thread::id main_thread = std::this_thread::get_id();

  const double cpu_before = cpu_seconds();
  const auto wall_before = std::chrono::steady_clock::now();
  const std::vector<TaskResult> results = rover::study::run_task_farm(
      tasks,
      [&](int i) {
        ++computed_here;
        return compute(i);
      },
      [&](const TaskResult& r) {
        reported.insert(r.index);
        reported_on_main_thread &= std::this_thread::get_id() == main_thread;
        checkpoint.add(r);
      },
      {.progress_interval_s = 1, .label = "probe", .progress = &std::cerr});
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_before).count();
  const double cpu = cpu_seconds() - cpu_before;

  std::vector<int> computed_per_rank(static_cast<std::size_t>(mpi.size()));
  MPI_Gather(&computed_here, 1, MPI_INT, computed_per_rank.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);

  if (root) {
    int total = 0, ranks_with_work = 0;
    std::cerr << "task_farm_probe: " << mpi.size() << " rank(s), tasks per rank:";
    for (const int n : computed_per_rank) {
      std::cerr << ' ' << n;
      total += n;
      ranks_with_work += n > 0;
    }
    std::cerr << "; rank 0 used " << cpu << " s CPU in " << wall << " s\n";
    check(total == kTasks, "each task computed exactly once (" + std::to_string(total) +
                               " computations for " + std::to_string(kTasks) + " tasks)");
    check(mpi.size() == 1 || ranks_with_work >= 2, "work reached more than one rank");
    check(reported.size() == static_cast<std::size_t>(kTasks) &&
              std::set<int>(reported.begin(), reported.end()).size() == reported.size(),
          "on_result called once per task");
    check(reported_on_main_thread, "on_result called on the main thread");
    check(results.size() == static_cast<std::size_t>(kTasks), "one result per task");
    for (std::size_t k = 0; k < results.size(); ++k) {
      const TaskResult& r = results[k];
      const std::string task = "task " + std::to_string(k) + ": ";
      check(r.index == static_cast<int>(k), task + "results sorted by index");
      if (r.index == kFailingTask) {
        check(r.status != 0 && r.message == "task 13 fails on purpose" && r.values.empty(),
              task + "recorded as failed with the exception's message");
      } else {
        check(r.status == 0 && r.message.empty(), task + "succeeded");
        check(r.values == expected_values(r.index), task + "values as computed");
      }
    }
    checkpoint.save();
    const std::vector<TaskResult> saved =
        rover::io::ResultCheckpoint(checkpoint_target, "probe").load();
    check(saved.size() == results.size(), "checkpoint holds every record");
    for (std::size_t k = 0; k < std::min(saved.size(), results.size()); ++k)
      check(saved[k].index == results[k].index && saved[k].status == results[k].status &&
                saved[k].message == results[k].message && saved[k].values == results[k].values,
            "checkpoint record " + std::to_string(k) + " equals the result");
    checkpoint.remove();

    // The output compared across rank counts.
    std::vector<int> index, status, length;
    std::vector<std::string> message;
    std::vector<double> values;
    for (const TaskResult& r : results) {
      index.push_back(r.index);
      status.push_back(r.status);
      length.push_back(static_cast<int>(r.values.size()));
      message.push_back(r.message);
      values.insert(values.end(), r.values.begin(), r.values.end());
    }
    rover::io::Hdf5Writer out(prefix + ".h5");
    out.write("/index", index);
    out.write("/status", status);
    out.write("/length", length);
    out.write("/message", message);
    out.write("/values", values);
    out.attribute("/", "tasks", kTasks);
    out.commit();
  }

  // --- an exception in on_result: rank 0 rethrows it after the workers are sent home
  bool thrown = false;
  try {
    int delivered = 0;
    const auto partial = rover::study::run_task_farm(tasks, compute,
                                                     [&](const TaskResult&) {
                                                       if (++delivered == 5)
                                                         throw std::runtime_error("disk full");
                                                     },
                                                     {.progress = nullptr});
    check(!root && partial.empty(), "workers return no results");
  } catch (const std::runtime_error& e) {
    thrown = std::string(e.what()) == "disk full";
  }
  if (root) check(thrown, "an exception from on_result reaches the caller on rank 0");

  // --- an invalid task list: refused on rank 0, the workers return
  thrown = false;
  try {
    rover::study::run_task_farm({1, 2, 1}, compute, nullptr, {.progress = nullptr});
  } catch (const std::invalid_argument&) {
    thrown = true;
  }
  if (root) check(thrown, "a task list with a duplicate is refused on rank 0");

  MPI_Barrier(MPI_COMM_WORLD);  // every rank got here: nobody is stuck in a farm
  if (root) std::cerr << "task_farm_probe: " << (failures ? "FAILED" : "OK") << std::endl;
  return failures ? 1 : 0;
}
