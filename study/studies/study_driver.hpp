// The one driver every study runs through (docs/studies.md): a study says what
// it computes, writes, reports and plots; the driver owns everything around
// that, the same for every study:
//   * the results path (results/<name>.h5 by default), checked before any run:
//     neither it nor the plots and checkpoint beside it replace an input,
//     and no plot beside it is a link or read-only;
//   * the memory estimate, refused up front beyond the limit;
//   * the checkpoint beside the result file, its fingerprint and --resume;
//   * SIGINT, SIGTERM, SIGHUP and SIGPIPE (InterruptGuard): stop handing out
//     runs, end the runs in progress
//     (not done: --resume computes them again) or the analysis after the runs
//     (WorkStopped), save the checkpoint, print the resume command, exit
//     status 130;
//   * the provenance attributes, the commit of the result file, the removal
//     of the checkpoint;
//   * the exit status: 0 done, kEveryRunFailedStatus when every run failed
//     (the results are kept), kSomeRunsFailedStatus when some failed for a
//     study that says so (evaluate), or the status the result itself asks
//     for (calibration: intervals that cannot be trusted);
//   * an earlier result at the results path is kept when every run failed or
//     the result holds nothing (a ranking of no candidate);
//   * --dry-run: everything above is checked and the banner printed, then
//     nothing runs and nothing is written.
//
// A study is a StudyProgram<Result>: its run is collective over the MPI ranks
// and returns a typed result that is meaningful on rank 0; write, report and
// plot take that result and are called on rank 0 only, in that order, after
// the run. The run prints nothing itself: progress goes through the task
// farm's progress lines.
#pragma once

#include <algorithm>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <ostream>
#include <string>
#include <vector>

#include "io/hdf5_file.hpp"
#include "io/input_files.hpp"
#include "io/output_lock.hpp"
#include "io/output_target.hpp"
#include "study/estimators/work_stopped.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/study_output.hpp"

namespace rover::study {

// The runs that finished with one kind of note (core/run_note.hpp: no wheel
// touched the ground, the friction law misses its parameters, ...).
struct NoteCount {
  std::string kind;
  long long runs = 0;
  std::string first;  // the note of the first run with this kind
};

// How many runs a study did, how many of them failed and how many finished
// with a note, per kind of note (a run with two problems counts under both).
struct RunCounts {
  long long runs = 0;
  long long failed = 0;
  std::string first_failure;  // the message of the first failed run
  long long noted = 0;        // runs with any note
  std::vector<NoteCount> notes;  // by kind, in the order of their first run
};

// The counts of runs of these statuses (run_status::kOk: done) and messages,
// with the message of the first that failed and the notes by kind.
RunCounts count_runs(const std::vector<int>& status, const std::vector<std::string>& messages);

// One line per kind of note, "K of N runs finished, but <first note> (the
// first of them)", at most kNoteKindsPrinted of them and then how many kinds
// more; none without notes.
inline constexpr std::size_t kNoteKindsPrinted = 6;
std::vector<std::string> note_lines(const RunCounts& counts);

// The bytes a study holds on rank 0 (`what` says what they are).
struct MemoryEstimate {
  std::string what;
  double bytes = 0.0;
};

// What a study's run gets from the driver.
struct StudyRuntime {
  StudyRunOptions options;       // for stream_study_tasks(): path, fingerprint, resume, progress, checkpoint
  io::Hdf5Writer* h5 = nullptr;  // rank 0: the open result file, for rows streamed in during the run
};

template <class Result>
struct StudyProgram {
  std::string command;      // "montecarlo": labels progress lines and messages
  std::string name;         // the study's name: results/<name>.h5 unless --out is given
  std::string fingerprint;  // every input and result-changing option (the checkpoint's key)
  std::string banner;       // what is about to run; rank 0 prints it first
  // What the study file asks that will cost failed runs (a distribution tail
  // the model refuses); rank 0 prints them after the banner.
  std::vector<std::string> warnings;
  MemoryEstimate memory;
  // The files the study reads; no output (the result, its plots, its
  // checkpoint) may replace one of them (io/input_files.hpp).
  io::InputFiles inputs;
  // Required. Collective: every rank calls it.
  std::function<Result(const StudyRuntime&)> run;
  // Rank 0 only, in this order.
  std::function<void(io::Hdf5Writer&)> provenance;            // root attributes
  std::function<void(const Result&, io::Hdf5Writer&)> write;  // the datasets
  // When set, a results path ending in .csv gets this instead of an HDF5 file.
  std::function<void(const Result&, const std::string& path)> write_csv;
  std::function<RunCounts(const Result&)> counts;
  std::function<void(const Result&, std::ostream&)> report;
  std::function<void(const Result&, const std::string& results_path, PlotSelection)> plot;
  // The figures `plot` writes with a selection (one entry per file it may
  // write): two that share a file name are refused before any run.
  std::function<std::vector<PlannedFigure>(PlotSelection)> figures;
  // The exit status when some runs, but not all, failed.
  int status_when_some_failed = 0;
  // The exit status the result asks for whatever its runs did (0: none); the
  // larger of it and the runs' status is returned.
  std::function<int(const Result&)> verdict;
  // Optional: why the result holds nothing (a ranking that ranked no
  // candidate), or empty. Such a result never replaces an earlier file at the
  // results path, as a study whose every run failed; with none there it is
  // written, recording why.
  std::function<std::string(const Result&)> holds_nothing;
};

// Thrown by a study whose runs finished but whose results it refuses (a
// sensitivity analysis with more failed runs than max_failed_fraction): the
// driver adds that nothing was written, where the runs are kept and
// `next_step`, what the next run of the study can do with them (a --resume
// of the same study would only refuse them again).
class RunsRefused : public std::runtime_error {
 public:
  RunsRefused(const std::string& what, std::string next_step)
      : std::runtime_error(what), next_step_(std::move(next_step)) {}
  const std::string& next_step() const { return next_step_; }

 private:
  std::string next_step_;
};

// The exit status of a study whose every run failed (its results are kept),
// of one whose some runs failed where the study counts that as an error, and
// of one whose result holds nothing (StudyProgram::holds_nothing).
inline constexpr int kEveryRunFailedStatus = 2;
inline constexpr int kSomeRunsFailedStatus = 2;
inline constexpr int kHoldsNothingStatus = 2;

namespace driver_detail {

// Checks the results path (neither it, nor a plot or the checkpoint beside
// it, may replace one of `inputs`; a plot beside it must be writable; no two
// of `figures` share a file name) and the memory estimate, completes
// `options` (results path, label, fingerprint) and prints the banner on rank 0.
StudyRunOptions prepare(const std::string& command, const std::string& name, const std::string& fingerprint,
                        const MemoryEstimate& memory, const std::string& banner, bool csv_allowed,
                        const io::InputFiles& inputs, const std::vector<PlannedFigure>& figures,
                        StudyRunOptions options);

bool is_csv_path(const std::string& path);

// Before any run of a study that will plot: gnuplot is on PATH
// (io::plotter_problem), else std::invalid_argument naming --no-plot.
void require_plotter();

// Commits the result file (if `h5` is not null: a CSV is already in place),
// removes the checkpoint and prints the one-line summary.
void commit(const std::string& command, const std::string& results_path, io::Hdf5Writer* h5,
            const RunCounts& counts);

// Rank 0, when every run failed, or the result holds nothing (`nothing`
// says why), and a file is already at results_path: the earlier result is
// left as it was (the runs stay in the checkpoint, when the study keeps one);
// says so and returns kEveryRunFailedStatus (kHoldsNothingStatus).
// std::nullopt otherwise.
std::optional<int> keep_earlier_result(const std::string& command, const std::string& results_path,
                                       const RunCounts& counts, const std::string& nothing);

// The exit status for `counts`; says so when every run failed.
int exit_status(const std::string& command, const std::string& results_path, const RunCounts& counts,
                int status_when_some_failed);

// What to say when the memory ran out while the study ran: its estimate,
// and where its finished runs are kept.
std::string out_of_memory(const MemoryEstimate& memory, const std::string& results_path);

// `message` of an error after the runs, and, when their checkpoint is
// there, that nothing was written, where the runs are kept and `next_step`.
std::string with_kept_runs(const std::string& message, const std::string& next_step,
                           const std::string& results_path);

// Prints the interrupt message; returns StudyInterrupted::kExitCode.
int interrupted(const std::string& command, const StudyInterrupted& e);

// Rank 0: throws StudyInterrupted when a signal arrived during a
// run that returned anyway (a calibration's probe, profiles or predictive
// draws stop handing out work and return what they have): such a result is
// incomplete and is never written. The message says where the finished runs
// are kept, if anywhere, and how to continue.
void stop_if_interrupted(const StudyRunOptions& options);
// The StudyInterrupted stop_if_interrupted() throws.
StudyInterrupted interruption(const StudyRunOptions& options);

// Collective: rank 0 takes the lock of the result (io/output_lock.hpp) and
// keeps it in the returned object (null elsewhere). Throws
// std::invalid_argument on every rank if another process holds it.
std::unique_ptr<io::OutputLock> lock_output(const std::string& results_path);

// Rank 0: says that a signal came once `results_path` was complete (while the
// report or the plots were made); returns the interrupted exit status.
int interrupted_after_commit(const std::string& command, const std::string& results_path);

// Rank 0: says that a dry run checked everything and ran nothing.
void report_dry_run(const std::string& command, const std::string& results_path);

// Rank 0: writes `result` to `out` (through `h5`, or as CSV without it) and
// commits it. A write that fails (a full disk) leaves no result, and the
// message says where the runs are kept and how to continue.
template <class Result>
void write_result(const StudyProgram<Result>& study, const Result& result, const std::string& out,
                  io::Hdf5Writer* h5, const StudyRunOptions& options, const RunCounts& counts) {
  try {
    if (h5 == nullptr) {
      study.write_csv(result, out);
    } else {
      if (study.provenance) study.provenance(*h5);
      study.write(result, *h5);
      stop_if_interrupted(options);  // while writing: uncommitted, the checkpoint kept
    }
    commit(study.command, out, h5, counts);
  } catch (const StudyInterrupted&) {
    throw;
  } catch (const WorkStopped&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(
        with_kept_runs(e.what(), "remove the cause (free space on a full disk) and run it again with --resume", out));
  }
}

}  // namespace driver_detail

// Collective: runs `study` with `options` (the user's flags) on every rank and
// returns the process exit status (meaningful on rank 0; 0 elsewhere).
// Throws std::invalid_argument before any run for an unusable results path
// or too large a memory estimate, and passes on the study's own errors.
template <class Result>
int drive_study(const StudyProgram<Result>& study, const StudyRunOptions& options) {
  StudyRuntime runtime;
  if (study.plot && options.plots != PlotSelection::kNone) driver_detail::require_plotter();
  const bool plots = study.plot && options.plots != PlotSelection::kNone;
  runtime.options = driver_detail::prepare(study.command, study.name, study.fingerprint, study.memory,
                                           study.banner, static_cast<bool>(study.write_csv), study.inputs,
                                           plots && study.figures ? study.figures(options.plots)
                                                                  : std::vector<PlannedFigure>{},
                                           options);
  if (world_rank() == 0)
    for (const std::string& warning : study.warnings) std::cerr << study.command << ": warning: " << warning << "\n";
  const std::string& out = runtime.options.results_path;
  if (options.dry_run) {
    if (world_rank() == 0) driver_detail::report_dry_run(study.command, out);
    return 0;
  }
  if (world_rank() != 0) {
    // A worker's part can end before rank 0's (its analysis); it then waits
    // for rank 0 in MPI_Finalize. mpirun signals every rank, and a worker
    // killed by the signal would make mpirun kill rank 0 before it reports:
    // a worker's signals stay a flag for the rest of its process.
    static const InterruptGuard worker_interrupts;
  }
  const InterruptGuard interrupts;  // from the first thing written on: a signal stops the study with its work saved
  if (world_rank() == 0) io::create_parent_directories(out);  // not for a dry run or a refusal
  const std::unique_ptr<io::OutputLock> lock = driver_detail::lock_output(out);
  const bool csv = driver_detail::is_csv_path(out);
  std::unique_ptr<io::Hdf5Writer> h5;
  if (world_rank() == 0 && !csv) h5 = std::make_unique<io::Hdf5Writer>(out);
  runtime.h5 = h5.get();
  try {
    const Result result = study.run(runtime);
    driver_detail::stop_if_interrupted(runtime.options);
    if (world_rank() != 0) return 0;
    const RunCounts counts = study.counts(result);
    const std::string nothing = study.holds_nothing ? study.holds_nothing(result) : std::string();
    if (const auto status = driver_detail::keep_earlier_result(study.command, out, counts, nothing)) return *status;
    driver_detail::write_result(study, result, out, h5.get(), runtime.options, counts);
    if (study.report) study.report(result, std::cerr);
    const bool every_run_failed = counts.runs > 0 && counts.failed == counts.runs;
    if (study.plot && options.plots != PlotSelection::kNone && !every_run_failed) {
      if (InterruptGuard::flag().load()) return driver_detail::interrupted_after_commit(study.command, out);
      study.plot(result, out, options.plots);
    }
    if (InterruptGuard::flag().load()) return driver_detail::interrupted_after_commit(study.command, out);
    const int status = driver_detail::exit_status(study.command, out, counts, study.status_when_some_failed);
    return study.verdict ? std::max(status, study.verdict(result)) : status;
  } catch (const StudyInterrupted& e) {
    return driver_detail::interrupted(study.command, e);
  } catch (const WorkStopped&) {  // a signal ended the analysis after the runs, or a run outside the farm
    return world_rank() == 0 ? driver_detail::interrupted(study.command, driver_detail::interruption(runtime.options))
                             : 0;
  } catch (const RunsRefused& e) {
    throw std::runtime_error(driver_detail::with_kept_runs(e.what(), e.next_step(), out));
  } catch (const std::bad_alloc&) {
    throw std::runtime_error(driver_detail::out_of_memory(study.memory, out));
  }
}

}  // namespace rover::study
