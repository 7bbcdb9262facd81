// The part every study shares: fan the runs out over MPI ranks (task_farm),
// checkpoint the finished ones beside the result file, and on --resume compute
// only what is missing. Results are written by rank 0 only.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "study/task_farm.hpp"

namespace rover::study {

// Rank of this process in MPI_COMM_WORLD (0 without MPI) and the rank count.
int world_rank();
int world_size();

struct StudyRunOptions {
  std::string results_path;   // the study's HDF5 file; the checkpoint lives beside it
  std::string fingerprint;    // identifies the configuration (config_fingerprint of its text)
  bool resume = false;        // reuse the checkpoint's finished runs
  std::string label = "study";
  int progress_interval_s = 5;
};

// Collective: every rank calls it. Runs compute(i) for i in [0, task_count)
// that are not in the checkpoint (all of them without --resume), and returns
// on rank 0 the results of all task_count runs, sorted by index (empty on the
// other ranks). The checkpoint stays until remove_checkpoint() is called,
// after the results are committed.
std::vector<TaskResult> run_study_tasks(int task_count,
                                        const std::function<TaskResult(int)>& compute,
                                        const StudyRunOptions& options);

void remove_checkpoint(const std::string& results_path);

}  // namespace rover::study
