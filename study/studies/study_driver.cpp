// See study_driver.hpp.
#include "study/studies/study_driver.hpp"
#include "study/runtime/rank0_broadcast.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string_view>

#include "core/run_note.hpp"
#include "io/checkpoint.hpp"
#include "io/output_target.hpp"
#include "io/plot.hpp"

#include "study/runtime/run_record.hpp"
#include "study/studies/study_output.hpp"

namespace rover::study {

RunCounts count_runs(const std::vector<int>& status, const std::vector<std::string>& messages) {
  RunCounts counts;
  counts.runs = static_cast<long long>(status.size());
  for (std::size_t i = 0; i < status.size(); ++i) {
    if (status[i] != run_status::kOk) {
      if (counts.failed++ == 0) counts.first_failure = messages[i];
      continue;
    }
    if (i >= messages.size() || messages[i].empty()) continue;
    ++counts.noted;
    std::set<std::string> kinds;  // of this run: each counted once
    for (const std::string& note : split_notes(messages[i])) {
      const std::string kind = note_kind(note);
      if (!kinds.insert(kind).second) continue;
      const auto known = std::find_if(counts.notes.begin(), counts.notes.end(),
                                       [&](const NoteCount& c) { return c.kind == kind; });
      if (known != counts.notes.end()) ++known->runs;
      else counts.notes.push_back({kind, 1, note});
    }
  }
  return counts;
}

std::vector<std::string> note_lines(const RunCounts& counts) {
  std::vector<std::string> lines;
  for (std::size_t k = 0; k < counts.notes.size() && k < kNoteKindsPrinted; ++k) {
    const NoteCount& c = counts.notes[k];
    lines.push_back(std::to_string(c.runs) + " of " + std::to_string(counts.runs) + " runs finished, but " + c.first +
                    (c.runs > 1 ? " (the first of them)" : ""));
  }
  if (counts.notes.size() > kNoteKindsPrinted)
    lines.push_back(std::to_string(counts.notes.size() - kNoteKindsPrinted) +
                    " more kinds of note; every run's notes are in the results (/samples/message)");
  return lines;
}

}  // namespace rover::study

namespace rover::study::driver_detail {

namespace {

// Refuses an output that would replace an input, and a plot beside it that
// may not be written, before any run.
void check_outputs(const std::string& flag, const std::string& out, const io::InputFiles& inputs,
                   PlotSelection plots) {
  std::vector<std::string> problems = io::outputs_over_inputs(
      flag, out, inputs,
      plots == PlotSelection::kNone ? io::WrittenBeside::kTemporaries : io::WrittenBeside::kTemporariesAndPlots);
  if (plots != PlotSelection::kNone)
    for (const std::string& problem : io::plots_beside_refused(out))
      problems.push_back(flag + " '" + out + "': the plot " + problem + "; or pass --plots none");
  if (problems.empty()) return;
  std::string text;
  for (const std::string& problem : problems) text += (text.empty() ? "" : "; ") + problem;
  throw std::invalid_argument(text);
}

// With --resume: a checkpoint of another configuration, or one that cannot be
// read, is refused now, not after the work before its runs (a calibration's
// fit). Reading it writes nothing.
void check_resumable(const std::string& results_path, const std::string& fingerprint) {
  std::error_code error;
  const std::string checkpoint = io::ResultCheckpoint::path_for(results_path);
  // The checkpoint is written in place, never through a link: a link there
  // (dangling or not) would let every run go ahead and then refuse to save.
  if (std::filesystem::is_symlink(std::filesystem::symlink_status(checkpoint, error)))
    throw std::invalid_argument("--resume: " + checkpoint + " is a symbolic link (to '" +
                                std::filesystem::read_symlink(checkpoint, error).string() +
                                "'); a checkpoint is never written through a link: put the file itself there, or "
                                "start afresh with --restart");
  if (!std::filesystem::exists(checkpoint, error)) {
    // Nothing to resume, and a finished result the runs would replace.
    if (std::filesystem::exists(std::filesystem::symlink_status(results_path, error)))
      throw std::invalid_argument("--resume: there is no checkpoint " + checkpoint + " to resume from, and " +
                                  results_path + " holds a finished result: there is nothing to resume; drop "
                                  "--resume to run the study again and replace it, or give another --out");
    return;
  }
  try {
    io::ResultCheckpoint(results_path, fingerprint).load();
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(e.what());
  }
}

// What every rank of one study must have been given alike: the study (its
// fingerprint: the files and the settings of its runs) and the flags that
// decide where and whether it runs.
std::string rank_agreement_text(const std::string& fingerprint, const StudyRunOptions& options) {
  return fingerprint + "\n--out " + options.results_path + (options.resume ? "\n--resume" : "") +
         (options.restart ? "\n--restart" : "") + (options.dry_run ? "\n--dry-run" : "") + "\n--plots " +
         std::to_string(static_cast<int>(options.plots));
}

// The result file's path, checked (see prepare) on this process.
std::string checked_output(const std::string& name, const std::string& fingerprint, bool csv_allowed,
                           const io::InputFiles& inputs, const std::vector<PlannedFigure>& figures,
                           const StudyRunOptions& options) {
  const bool given = !options.results_path.empty() && !options.results_path_is_default;
  // An input the output would destroy comes first, before the path's form;
  // a study that draws no figure (a ranking, --plots none) writes no plot.
  check_outputs(given ? "--out" : "--out (default)",
                options.results_path.empty() ? "results/" + name + ".h5" : options.results_path, inputs,
                figures.empty() ? PlotSelection::kNone : options.plots);
  const std::string results_path =
      checked_results_path(name, options.results_path, csv_allowed, options.results_path_is_default);
  if (const std::string shared = shared_figure_names(results_path, figures); !shared.empty())
    throw std::invalid_argument("--plots: " + shared + ", one replacing the other: give the QoI another \"label\", "
                                "or pass --plots summary or --plots none");
  for (const PlannedFigure& figure : figures) {
    const std::string path = sibling_path(results_path, figure.suffix);
    if (const std::string refusal = io::name_length_refusal(path, io::kFigureTemporarySuffix); !refusal.empty())
      throw std::invalid_argument("--plots: the figure of " + figure.shows + ", " + path + ": " + refusal +
                                  " (shorten --out), or pass --plots none");
  }
  if (options.resume) check_resumable(results_path, fingerprint);
  return results_path;
}

}  // namespace

StudyRunOptions prepare(const std::string& command, const std::string& name, const std::string& fingerprint,
                        const MemoryEstimate& memory, const std::string& banner, bool csv_allowed,
                        const io::InputFiles& inputs, const std::vector<PlannedFigure>& figures,
                        StudyRunOptions options) {
  // The checks probe the file system (a file made and removed, a directory
  // made and removed): rank 0 alone makes them, and every rank follows its
  // verdict. Ranks probing one new directory at once would see each other's
  // probes come and go, and one refusing alone would leave the others
  // waiting for it forever.
  std::string refusal;
  std::string results_path = options.results_path.empty() ? "results/" + name + ".h5" : options.results_path;
  if (world_rank() == 0) {
    try {
      results_path = checked_output(name, fingerprint, csv_allowed, inputs, figures, options);
    } catch (const std::invalid_argument& e) {
      refusal = e.what();
    }
  }
  if (broadcast_flag_from_rank0(!refusal.empty()))
    throw std::invalid_argument(refusal.empty() ? "refused on rank 0 (which says why)" : refusal);
  // Ranks started with other study files, flags or inputs (an MPMD launch)
  // would each run their own study into one result.
  if (differs_from_rank0_anywhere(rank_agreement_text(fingerprint, options)))
    throw std::invalid_argument("the ranks were not all given the same study: another rank's study file, flags "
                                "(--out, --resume, --restart, --dry-run and --plots among them) or input files "
                                "differ from rank 0's (launched with other command lines?), and the ranks would "
                                "run different studies into one result, or wait for each other forever; give "
                                "every rank the same command");
  options.results_path = results_path;
  if (memory.bytes > 0.0) require_memory(memory.what, memory.bytes);
  options.label = command;
  options.fingerprint = fingerprint;
  if (world_rank() == 0 && !banner.empty()) std::cerr << command << ": " << banner << "\n";
  return options;
}

bool is_csv_path(const std::string& path) { return path.ends_with(".csv"); }

void require_plotter() {
  if (const std::string problem = io::plotter_problem(); !problem.empty())
    throw std::invalid_argument("--plots: the study's figures need gnuplot (with the pngcairo terminal), but " +
                                problem + ", or pass --no-plot (--plots none)");
}

void commit(const std::string& command, const std::string& results_path, io::Hdf5Writer* h5,
            const RunCounts& counts) {
  if (h5 != nullptr) h5->commit();
  remove_checkpoint(results_path);
  std::cerr << command << ": ";
  if (counts.runs > 0) std::cerr << counts.runs << " runs (" << counts.failed << " failed), ";
  std::cerr << "wrote " << results_path << "\n";
  for (const std::string& line : note_lines(counts)) std::cerr << command << ": WARNING: " << line << "\n";
}

std::optional<int> keep_earlier_result(const std::string& command, const std::string& results_path,
                                       const RunCounts& counts, const std::string& nothing) {
  std::error_code error;
  const bool every_run_failed = counts.runs > 0 && counts.failed == counts.runs;
  if ((!every_run_failed && nothing.empty()) || !std::filesystem::exists(results_path, error)) return std::nullopt;
  // A study that checkpoints its runs (a Monte Carlo) still has them; a
  // calibration's fit keeps none.
  const std::string checkpoint = io::ResultCheckpoint::path_for(results_path);
  const bool kept = std::filesystem::exists(checkpoint, error);
  std::cerr << "rover " << command << ": error: "
            << (every_run_failed ? "every run failed (first: " + counts.first_failure + ")" : nothing)
            << "; nothing was written, " << results_path << " is unchanged"
            << (kept ? "; the runs are kept in " + checkpoint +
                           ": the next run of this study needs --restart (discard them) or --resume (reuse them)"
                     : std::string(every_run_failed ? "; no run was kept" : ""))
            << "\n";
  return every_run_failed ? kEveryRunFailedStatus : kHoldsNothingStatus;
}

int exit_status(const std::string& command, const std::string& results_path, const RunCounts& counts,
                int status_when_some_failed) {
  if (counts.failed == 0) return 0;
  if (counts.failed < counts.runs) return status_when_some_failed;
  std::cerr << "rover " << command << ": error: every run failed (first: " << counts.first_failure
            << "); the results are in " << results_path << "\n";
  return kEveryRunFailedStatus;
}

std::unique_ptr<io::OutputLock> lock_output(const std::string& results_path) {
  std::unique_ptr<io::OutputLock> lock;
  std::string refusal;
  if (world_rank() == 0) {
    try {
      lock = std::make_unique<io::OutputLock>(results_path);
    } catch (const std::runtime_error& e) {
      refusal = e.what();
    }
  }
  if (broadcast_flag_from_rank0(!refusal.empty())) throw std::invalid_argument(refusal.empty() ? "the result is locked (rank 0 says why)" : refusal);
  return lock;
}

void report_dry_run(const std::string& command, const std::string& results_path) {
  std::cerr << command << ": dry run: the inputs are read and checked, " << results_path
            << " can be written; nothing was run or written\n";
}

std::string out_of_memory(const MemoryEstimate& memory, const std::string& results_path) {
  char estimate[96] = "";
  if (memory.bytes > 0.0) std::snprintf(estimate, sizeof estimate, " (about %.3g GB of ", memory.bytes / 1e9);
  const std::string what = memory.bytes > 0.0 ? estimate + memory.what + " were estimated)" : std::string();
  return with_kept_runs("out of memory while running the study" + what +
                            ": reduce --samples or the study's size, or run it where more memory is free",
                        "--resume continues from them", results_path);
}

std::string with_kept_runs(const std::string& message, const std::string& next_step,
                           const std::string& results_path) {
  const std::string checkpoint = io::ResultCheckpoint::path_for(results_path);
  std::error_code error;
  if (world_rank() != 0 || !std::filesystem::exists(checkpoint, error)) return message;
  return message + "\nNothing was written; the finished runs are kept in " + checkpoint + ": " + next_step;
}

int interrupted(const std::string& command, const StudyInterrupted& e) {
  // The task farm labels its message with the command already: said once.
  std::string_view what = e.what();
  if (const std::string label = command + ": "; what.starts_with(label)) what.remove_prefix(label.size());
  std::cerr << "rover " << command << ": " << what << std::endl;
  return StudyInterrupted::kExitCode;
}

int interrupted_after_commit(const std::string& command, const std::string& results_path) {
  std::cerr << "rover " << command << ": interrupted (" << InterruptGuard::signal_name() << ") after "
            << results_path << " was written: it is complete; plots not yet drawn were skipped\n";
  return StudyInterrupted::kExitCode;
}

StudyInterrupted interruption(const StudyRunOptions& options) {
  const std::string checkpoint = io::ResultCheckpoint::path_for(options.results_path);
  std::error_code error;
  const bool kept = std::filesystem::exists(checkpoint, error);
  const std::string resume =
      options.resume_command.empty() ? std::string("the same command with --resume") : options.resume_command;
  return StudyInterrupted("interrupted (" + InterruptGuard::signal_name() +
                          ") before the study was complete; nothing was written" +
                          (kept ? "; the finished runs are kept in " + checkpoint + ". Continue with:\n  " + resume
                                : std::string("; run the same command again")));
}

void stop_if_interrupted(const StudyRunOptions& options) {
  if (world_rank() != 0 || !InterruptGuard::flag().load()) return;
  throw interruption(options);
}

}  // namespace rover::study::driver_detail
