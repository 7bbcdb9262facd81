// The part every study shares: fan the runs out over MPI ranks (task_farm),
// checkpoint the finished ones beside the result file, and on --resume compute
// only what is missing. Results are written by rank 0 only.
#pragma once

#include <atomic>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/checkpoint.hpp"
#include "study/runtime/task_farm.hpp"
#include "study/surrogate/gaussian_process.hpp"

namespace rover::study {

// Rank of this process in MPI_COMM_WORLD (0 without MPI) and the rank count.
int world_rank();
int world_size();

// The figures a study writes beside its result file: none, its one summary
// figure, or the summary and one figure per QoI and channel.
enum class PlotSelection { kNone, kSummary, kAll };

// How a study runs: where its results and checkpoint go, what identifies it,
// how it reports progress and what it plots.
struct StudyRunOptions {
  std::string results_path;   // the study's HDF5 file; the checkpoint lives beside it
  bool results_path_is_default = false;  // set by the command, not by --out (messages then say so)
  std::string fingerprint;    // identifies the configuration (config_fingerprint of its text)
  bool resume = false;        // reuse the checkpoint's finished runs
  bool restart = false;       // discard a leftover checkpoint (the drivers refuse one without --resume or --restart)
  std::string label = "study";
  int progress_interval_s = 5;
  std::string resume_command;  // the command line that resumes the study (for messages)
  io::CheckpointPolicy checkpoint;  // how often finished runs are flushed to the checkpoint
  PlotSelection plots = PlotSelection::kSummary;
  bool dry_run = false;  // read and check every input and output, print what would run, run nothing
};

// Collective: every rank calls it. stream_study_tasks() (below) collecting
// the records: returns on rank 0 the results of all task_count runs, sorted by
// index (empty on the other ranks), for studies whose runs are few. The checkpoint stays until remove_checkpoint() is called,
// after the results are committed.
std::vector<TaskResult> run_study_tasks(int task_count,
                                        const std::function<TaskResult(int)>& compute,
                                        const StudyRunOptions& options);

void remove_checkpoint(const std::string& results_path);

// After ResultCheckpoint::load() on --resume: says on stderr, prefixed with
// `label`, how many bytes at the checkpoint's end were no intact record and
// were dropped, so that their `records` ("runs", "steps") are computed again.
void report_dropped_checkpoint_bytes(const io::ResultCheckpoint& checkpoint, const std::string& label,
                                     const std::string& records);

// A study stopped by a signal (InterruptGuard): what is done is in the checkpoint.
// what() says so and gives the --resume hint; the program exits with
// kExitCode.
class StudyInterrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  static constexpr int kExitCode = 130;
};

// While alive, SIGINT, SIGTERM and SIGHUP (a closed terminal or ssh
// session) set a flag that makes the running study stop handing out work
// instead of killing the process (the finished runs are kept), and so does
// SIGPIPE (output into a pipe whose reader is gone, `rover ... | head`).
// A second signal kills as usual, unless it comes within kSignalRepeatWindow_s
// of the first: `timeout`, batch systems and process groups often deliver one
// request twice, and that is still the one request to stop. SIGPIPE never
// kills (every write to the closed pipe raises it again). SIGQUIT keeps its
// default action (a core dump, which is what it asks for). Guards nest: an
// inner one (a study run inside the study driver's) keeps the outer one's
// flag and handlers.
class InterruptGuard {
 public:
  static constexpr double kSignalRepeatWindow_s = 1.0;
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;
  // The flag; the task farm also raises it on rank 0 when a worker rank was
  // signalled alone (task_farm.hpp, TaskFarmOptions::stop).
  static std::atomic<bool>& flag();
  // The signal that raised the flag, for messages: "SIGINT", "SIGTERM",
  // "SIGHUP", "SIGPIPE: an output pipe was closed", or "a signal" (raised
  // for a worker rank's signal).
  static std::string signal_name();
};

// Until the first InterruptGuard, SIGINT, SIGTERM or SIGHUP ends the process
// at once with StudyInterrupted::kExitCode and a one-line message: the
// program is reading its inputs (perhaps waiting on a pipe) and has written
// nothing. Outside the guards SIGPIPE only fails the write to the closed
// pipe (reported as an error, drivers/main.cpp), and is remembered: the next
// guard starts with its flag raised (a study whose banner went into a pipe
// whose reader has gone stops at its start).
// The first guard retires this (the handlers it restores are the system's),
// and so does retire_exit_on_interrupt(), called by a command that begins to
// write without a guard: a signal then ends it as the system does.
void exit_on_interrupt_until_guarded();
void retire_exit_on_interrupt();

// `settings` whose likelihood maximisation stops when a signal arrives
// (InterruptGuard::flag()): a kriging fit of thousands of runs ends within an
// evaluation, not after its starts.
GaussianProcessSettings interruptible(GaussianProcessSettings settings);

// Collective: every rank calls it. Runs compute(i) for every i in
// [0, task_count) that the checkpoint does not hold (all, without --resume),
// and on rank 0 calls consume(record) exactly once for EVERY index, the
// checkpointed ones included, in index order, while results come in. Nothing
// is kept but the records that arrive ahead of a missing index, so memory does
// not grow with task_count, and every accumulation in consume() sees the same
// order on any number of ranks. On rank 0, a signal ends it with
// StudyInterrupted after the checkpoint is saved (`resume_command` is quoted).
void stream_study_tasks(int task_count, const std::function<TaskResult(int)>& compute,
                        const std::function<void(TaskResult&&)>& consume,
                        const StudyRunOptions& options);

}  // namespace rover::study
