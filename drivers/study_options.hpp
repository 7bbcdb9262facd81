// The command-line side of the study driver (study/studies/study_driver.hpp):
// the flags every study subcommand shares, the resume command rebuilt from
// the flags the user gave, and run_study_command(), which a subcommand calls
// with a function that loads its study into a StudyProgram.
#pragma once

#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "drivers/options.hpp"
#include "io/checkpoint.hpp"
#include "io/input_files.hpp"
#include "io/output_lock.hpp"
#include "study/runtime/mpi_session.hpp"
#include "study/runtime/rank0_broadcast.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/evaluate.hpp"
#include "study/studies/study_driver.hpp"

namespace rover::cli {

inline constexpr int kMaxProgressIntervalS = 86400;
inline constexpr int kMaxCheckpointEvery = 1000000;

// --progress-interval and --checkpoint-every, with their ranges.
inline void add_progress_flags(CLI::App& app, study::StudyRunOptions& o) {
  app.add_option("--progress-interval", o.progress_interval_s, "Seconds between progress lines")
      ->capture_default_str()->check(CLI::Range(1, kMaxProgressIntervalS));
  app.add_option("--checkpoint-every", o.checkpoint.every_records,
                 "Flush finished runs to <out>.checkpoint after this many (or every 60 s)")
      ->capture_default_str()->check(CLI::Range(1, kMaxCheckpointEvery));
}

inline void add_output_flags(CLI::App& app, study::StudyRunOptions& o) {
  app.add_option("--out", o.results_path, "HDF5 result file (default results/<study name>.h5)");
  app.add_flag("--resume", o.resume,
               "Continue an interrupted study from its checkpoint (<out>.checkpoint): only the "
               "missing runs are computed");
  app.add_flag("--restart", o.restart,
               "Discard the checkpoint of an interrupted study (<out>.checkpoint) and start afresh");
}

// --dry-run: everything is read and checked, nothing runs.
inline void add_dry_run_flag(CLI::App& app, study::StudyRunOptions& o) {
  app.add_flag("--dry-run", o.dry_run,
               "Read and check the study, every file it names and --out, print what would run, and stop: "
               "nothing is run or written");
}

// --plots (and --no-plot, the same as --plots none).
inline void add_plots_flags(CLI::App& app, study::StudyRunOptions& o) {
  static const std::map<std::string, study::PlotSelection> kPlots{{"none", study::PlotSelection::kNone},
                                                                   {"summary", study::PlotSelection::kSummary},
                                                                   {"all", study::PlotSelection::kAll}};
  CLI::Option* plots =
      app.add_option_function<std::string>(
             "--plots", [&o](const std::string& value) { o.plots = kPlots.at(value); },
             "Figures beside the result file: summary (one figure), all (also one per QoI and channel) or none")
          ->check(CLI::IsMember({"summary", "all", "none"}))
          ->type_name("WHICH")
          ->default_str("summary");
  // Both given, the later one would win silently: "--plots all --no-plot" is refused.
  app.add_flag_callback("--no-plot", [&o] { o.plots = study::PlotSelection::kNone; }, "Same as --plots none")
      ->excludes(plots);
}

// The flags of every study subcommand: --out, --resume, --restart, --dry-run,
// --plots, --no-plot, --progress-interval, --checkpoint-every.
inline void add_study_flags(CLI::App& app, study::StudyRunOptions& o) {
  add_output_flags(app, o);
  add_dry_run_flag(app, o);
  add_plots_flags(app, o);
  add_progress_flags(app, o);
}

// A leftover checkpoint: the finished runs of a study that stopped before
// its end are kept unless the command says what to do with them.
inline void check_leftover_checkpoint(FlagChecks& checks, const std::string& results_path, bool resume,
                                      bool restart) {
  if (resume && restart)
    checks.add("--resume and --restart exclude each other: --resume continues <out>.checkpoint, --restart "
               "discards it");
  if (results_path.empty()) return;
  // A running study's checkpoint is not leftover: neither --resume nor --restart may touch it.
  // Rank 0 probes (the other ranks would see rank 0's own lock once it runs) and tells every rank.
  if (study::broadcast_flag_from_rank0(study::world_rank() == 0 && io::OutputLock::held_elsewhere(results_path))) {
    checks.add(io::OutputLock::held_message(results_path));
    return;
  }
  const std::string checkpoint = io::ResultCheckpoint::path_for(results_path);
  std::error_code error;
  const std::filesystem::file_status there = std::filesystem::symlink_status(checkpoint, error);
  // Only a file or a link can be a checkpoint: anything else is never read or discarded.
  if (std::filesystem::exists(there) && !std::filesystem::is_regular_file(there) &&
      !std::filesystem::is_symlink(there)) {
    checks.add(checkpoint + " is no checkpoint (not a regular file): remove it, or give another --out");
    return;
  }
  if (!std::filesystem::exists(there)) return;
  // A file that does not begin as a checkpoint was never written by rover: it is
  // someone's data (an input of this very command, perhaps), never removed, not
  // even with --restart. (--resume reads it, and refuses it, before any run.)
  if (!resume && io::ResultCheckpoint::is_foreign_file(checkpoint)) {
    checks.add(checkpoint + " is no checkpoint of rover (it does not begin as one), and rover never removes such "
               "a file: give another --out");
    return;
  }
  if (resume || restart) return;
  if (std::filesystem::is_symlink(there))
    checks.add(checkpoint + " is a symbolic link, which no checkpoint is: --restart removes the link, or give "
               "another --out");
  else if (std::filesystem::hard_link_count(checkpoint, error) > 1)
    checks.add(checkpoint + " is one of several names of a file (a hard link), which no checkpoint is: --restart "
               "removes this name (the file keeps its others), or give another --out");
  else
    checks.add(checkpoint + " holds the finished runs of a study that stopped before its end (interrupted, or "
               "ended by failed runs); continue it with --resume if it is this same study, or discard them and "
               "start afresh with --restart");
}

// Where a study writes: --out, or results/<name>.h5 with the "name" of the
// study file (empty when the file has none: its loader will say so).
inline std::string study_results_path(const study::StudyRunOptions& c, const std::string& study_path) {
  if (!c.results_path.empty()) return c.results_path;
  std::ifstream in(study_path, std::ios::binary);
  std::string text;
  try {
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::exception&) {
    return "";
  }
  const io::Json json = io::parse_json_quietly(text);
  if (!json.is_object() || !json.contains("name") || !json["name"].is_string()) return "";
  const std::string name = json["name"].get<std::string>();
  return name.empty() ? "" : "results/" + name + ".h5";
}

// The checks of where a study writes that need no study loaded: --out is a
// file in a directory that can be made; a leftover checkpoint needs --resume
// or --restart. The study driver checks the rest once the study is loaded:
// no output over a file the loader read, no plot path it may not write.
inline void check_study_output_path(FlagChecks& checks, const study::StudyRunOptions& c,
                                    const std::string& study_path) {
  checks.output_file(c.results_path_is_default ? "the default output" : "--out", c.results_path,
                     /*regular_only=*/true);
  check_leftover_checkpoint(checks, study_results_path(c, study_path), c.resume, c.restart);
}

// The command that continues this one: `rover <subcommand>`, every flag the
// user gave, in the order given, with its values (each quoted where the shell
// needs it), and --resume.
std::string resume_command(const CLI::App& subcommand);

// Runs a study subcommand: the MPI session, the checks of --out's form and of
// a leftover checkpoint, then `run` with the options completed by the resume
// command (run loads the study and calls study::drive_study, which checks the
// outputs against the program's inputs). Returns the exit status.
template <class Run>
int run_study_session(const CLI::App& subcommand, study::StudyRunOptions options, const std::string& study_path,
                      Run&& run) {
  study::MpiSession mpi(nullptr, nullptr);
  FlagChecks checks;
  check_study_output_path(checks, options, study_path);
  // Rank 0 alone probes --out's directory: its verdict is every rank's.
  if (study::broadcast_flag_from_rank0(checks.any()) && !checks.any())
    throw std::invalid_argument("--out is refused on rank 0 (which says why)");
  checks.throw_if_any();
  options.resume_command = resume_command(subcommand);
  return run(options);
}

// The inputs the outputs must not replace: the study file and the files its
// loader read (`listed`); a loader that lists none has every file named
// inside the study file taken instead (io::InputFiles::add_config).
inline io::InputFiles study_inputs(const std::string& study_path, const io::InputFiles& listed) {
  io::InputFiles inputs;
  if (listed.files().empty()) {
    inputs.add_config(study_path, "--study");
  } else {
    inputs.add(study_path, "--study");
    inputs.add_all(listed);
  }
  return inputs;
}

// run_study_session for a subcommand whose `load` reads the study file,
// applies the flags and returns the study's StudyProgram.
template <class Load>
int run_study_command(const CLI::App& subcommand, const study::StudyRunOptions& options,
                      const std::string& study_path, Load&& load) {
  return run_study_session(subcommand, options, study_path, [&](const study::StudyRunOptions& completed) {
    auto program = load();
    program.inputs = study_inputs(study_path, program.inputs);
    return study::drive_study(program, completed);
  });
}

inline constexpr const char* kMpiFooter =
    "Parallel: every study runs unchanged as `mpirun -np N rover ...`; runs are handed out\n"
    "dynamically, rank 0 writes the results, and they do not depend on N. As root, Open MPI\n"
    "needs OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 (and --oversubscribe\n"
    "for more ranks than cores). A crash leaves no half-written result file: finished runs\n"
    "are kept in <out>.checkpoint and `--resume` computes only the missing ones.";

}  // namespace rover::cli
