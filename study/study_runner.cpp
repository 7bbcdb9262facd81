#include "study/study_runner.hpp"

#include <filesystem>
#include <iostream>
#include <map>

#include <mpi.h>

#include "io/checkpoint.hpp"

namespace rover::study {

int world_rank() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  int rank = 0;
  if (initialized) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int world_size() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  int size = 1;
  if (initialized) MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

std::vector<TaskResult> run_study_tasks(int task_count,
                                        const std::function<TaskResult(int)>& compute,
                                        const StudyRunOptions& options) {
  const bool root = world_rank() == 0;
  std::vector<TaskResult> done;
  std::vector<int> todo;
  std::unique_ptr<io::ResultCheckpoint> checkpoint;
  if (root) {
    if (const auto dir = std::filesystem::path(options.results_path).parent_path(); !dir.empty())
      std::filesystem::create_directories(dir);
    checkpoint = std::make_unique<io::ResultCheckpoint>(options.results_path, options.fingerprint);
    if (options.resume) {
      done = checkpoint->load();
      std::cerr << options.label << ": resuming, " << done.size() << " of " << task_count
                << " runs already done (" << checkpoint->path() << ")\n";
    } else if (std::filesystem::exists(checkpoint->path())) {
      std::cerr << options.label << ": starting afresh; the old checkpoint " << checkpoint->path()
                << " is replaced (use --resume to continue it)\n";
      checkpoint->remove();
    }
    todo = io::missing_indices(task_count, done);
  }
  TaskFarmOptions farm;
  farm.label = options.label;
  farm.progress_interval_s = options.progress_interval_s;
  std::vector<TaskResult> fresh = run_task_farm(
      todo, compute, [&](const TaskResult& r) { checkpoint->add(r); }, farm);
  if (!root) return {};
  checkpoint->save();
  std::map<int, TaskResult> all;
  for (auto& r : done) all[r.index] = std::move(r);
  for (auto& r : fresh) all[r.index] = std::move(r);
  std::vector<TaskResult> out;
  out.reserve(all.size());
  for (auto& [index, r] : all) out.push_back(std::move(r));
  return out;
}

void remove_checkpoint(const std::string& results_path) {
  std::error_code ignored;
  std::filesystem::remove(io::ResultCheckpoint::path_for(results_path), ignored);
}

}  // namespace rover::study
