// Dynamic distribution of independent tasks (Monte Carlo runs, response-surface
// grid points, calibration evaluations) over the ranks of MPI_COMM_WORLD.
//
// Tasks differ in cost a lot (0.05 s to several seconds per run), so they are
// handed out one at a time on request, in the order given (put the expensive
// ones first to shorten the tail). Rank 0 runs a communication thread (the
// master: it answers work requests, receives results) while its main thread
// computes tasks from the same queue, so `mpirun -np 2` on 2 cores keeps both
// busy. Workers keep one task in hand ahead of the one they compute.
//
// Threads and MPI: MPI must have been initialised with at least
// MPI_THREAD_SERIALIZED (study/runtime/mpi_session.hpp). While the farm runs, rank 0's
// communication thread is the only thread calling MPI; compute() and on_result
// must not call MPI. Without MPI initialised, or on a single rank, the tasks run
// in a plain loop.
#pragma once

#include <atomic>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "io/task_record.hpp"

namespace rover::study {

// One finished task: index, status (0 = ok, nonzero = the run failed; the study
// goes on and records it), message (why it failed) and the run's values. The
// same record the checkpoint stores.
using TaskResult = io::TaskRecord;

// Progress goes to `progress` on rank 0 only: a line every progress_interval_s
// seconds (see progress_line()) and a summary line at the end.
struct TaskFarmOptions {
  int progress_interval_s = 5;          // <= 0: the summary line only
  std::string label = "tasks";          // lines start with "<label>: "
  std::ostream* progress = &std::cerr;  // nullptr: silent
  // false: results go to on_result only and the returned vector is empty
  // (memory independent of the number of tasks).
  bool keep_results = true;
  // When it becomes true (e.g. set by a signal handler), no further task is
  // handed out; the tasks in progress finish (or stop midway: WorkStopped) and
  // are delivered, and the farm returns with fewer results than tasks. A
  // worker rank whose own flag is set (mpirun signals every rank) gives back
  // the tasks it holds unrun; rank 0 then sets its own flag, so a signal to
  // one worker's process stops the farm as a signal to rank 0 does.
  std::atomic<bool>* stop = nullptr;
  // Under MPI (more than one rank), called once on rank 0 as soon as the stop
  // is seen, after every result received so far went to on_result. It runs on
  // the communication thread, while rank 0's own task may still be computing,
  // so that a checkpoint can be flushed before mpirun's SIGKILL (Open MPI 4.1
  // sends it 1 s after SIGTERM); from then on the workers' results go to
  // on_result from that thread too, as they arrive. Calls of on_result and
  // on_stop never overlap. (A single process returns at once after a stop.)
  std::function<void()> on_stop = nullptr;
};

// Runs compute(i) for every i in `tasks` (distinct, non-negative indices; only
// rank 0's list is used) on all ranks. compute() may throw: the task is then
// recorded as failed (status 1, message = what()), except for WorkStopped
// (study/estimators/work_stopped.hpp), which compute() throws once `stop` is set
// to end a long task midway: that task is not done (no result; a worker hands
// it back). The result's index is set
// to i. on_result is called on rank 0 only, once per finished task, in
// completion order (for checkpointing), in the calling thread (after a stop,
// also the communication thread: see on_stop; never two calls at once). Returns, on rank 0,
// all results sorted by index; on other ranks, an empty vector. The values are
// exactly what compute() returned, whatever the number of ranks.
//
// Collective: every rank of MPI_COMM_WORLD must call it. If rank 0 throws (an
// exception from on_result, or invalid `tasks`), it stops handing out work,
// waits for the workers' tasks in progress, and rethrows; the workers return.
std::vector<TaskResult> run_task_farm(const std::vector<int>& tasks,
                                      const std::function<TaskResult(int)>& compute,
                                      const std::function<void(const TaskResult&)>& on_result,
                                      const TaskFarmOptions& options = {});

// "label: 123/1000 done (2 failed), 4.1 runs/s, ETA 3m12s" (the progress line).
std::string progress_line(const std::string& label, std::size_t done, std::size_t total,
                          std::size_t failed, double elapsed_s);

}  // namespace rover::study
