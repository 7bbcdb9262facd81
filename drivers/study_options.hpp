// The command-line side of the study driver (study/studies/study_driver.hpp):
// the flags every study subcommand shares, the resume command rebuilt from
// the flags the user gave, and run_study_command(), which a subcommand calls
// with a function that loads its study into a StudyProgram.
#pragma once

#include <iostream>
#include <map>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "drivers/options.hpp"
#include "study/runtime/mpi_session.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/study_config.hpp"
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
}

// --plots (and --no-plot, the same as --plots none).
inline void add_plots_flags(CLI::App& app, study::StudyRunOptions& o) {
  static const std::map<std::string, study::PlotSelection> kPlots{{"none", study::PlotSelection::kNone},
                                                                   {"summary", study::PlotSelection::kSummary},
                                                                   {"all", study::PlotSelection::kAll}};
  app.add_option_function<std::string>(
         "--plots", [&o](const std::string& value) { o.plots = kPlots.at(value); },
         "Figures beside the result file: summary (one figure), all (also one per QoI and channel) or none")
      ->check(CLI::IsMember({"summary", "all", "none"}))
      ->type_name("WHICH")
      ->default_str("summary");
  app.add_flag_callback("--no-plot", [&o] { o.plots = study::PlotSelection::kNone; }, "Same as --plots none");
}

// The flags of every study subcommand: --out, --resume, --plots, --no-plot,
// --progress-interval, --checkpoint-every.
inline void add_study_flags(CLI::App& app, study::StudyRunOptions& o) {
  add_output_flags(app, o);
  add_plots_flags(app, o);
  add_progress_flags(app, o);
}

// used by calibration until it moves to the study driver: the flags above
// with calibration's on/off plot switch.
inline void add_study_control(CLI::App& app, study::StudyRunControl& c) {
  add_output_flags(app, c);
  app.add_flag("!--no-plot", c.plot, "Do not write PNG plots");
  add_progress_flags(app, c);
}

// The checks of a study's --out (a file, in a directory that can be made, not
// the study file itself), before the study is loaded.
inline void check_study_output(FlagChecks& checks, const study::StudyRunOptions& o, const std::string& study_path) {
  checks.output_file("--out", o.results_path, /*regular_only=*/true);
  checks.distinct_files("--out", o.results_path, "--study", study_path);
}

// An --integrator flag names a method.
inline void check_integrator_flag(FlagChecks& checks, const std::string& name) {
  if (name.empty()) return;
  try {
    integrator_from_name(name);
  } catch (const std::invalid_argument& e) {
    checks.add(std::string("--integrator: ") + e.what());
  }
}

// The command that continues this one: `rover <subcommand>`, every flag the
// user gave, in the order given, with its values (each quoted where the shell
// needs it), and --resume.
std::string resume_command(const CLI::App& subcommand);

// Runs a study subcommand: the MPI session, the checks of --out against the
// study file, then `load` (which reads the study file, applies the flags and
// returns the study's StudyProgram), then the study driver. Returns the exit
// status.
template <class Load>
int run_study_command(const CLI::App& subcommand, study::StudyRunOptions options, const std::string& study_path,
                      Load&& load) {
  study::MpiSession mpi(nullptr, nullptr);
  FlagChecks checks;
  check_study_output(checks, options, study_path);
  checks.throw_if_any();
  const auto program = load();
  options.resume_command = resume_command(subcommand);
  return study::drive_study(program, options);
}

// used by calibration until it moves to the study driver, which handles the
// interrupt itself. Runs a study inside the command's MPI session and reports
// an interrupt there (exit status 130): after a Ctrl-C of mpirun,
// MPI_Finalize does not return before Open MPI kills the rank, so a message
// printed after the session ended would be lost.
template <class Study>
int run_interruptible(const std::string& command, Study&& run_study) {
  try {
    return run_study();
  } catch (const study::StudyInterrupted& e) {
    std::cerr << "rover " << command << ": " << e.what() << std::endl;
    return study::StudyInterrupted::kExitCode;
  }
}

inline constexpr const char* kMpiFooter =
    "Parallel: every study runs unchanged as `mpirun -np N rover ...`; runs are handed out\n"
    "dynamically, rank 0 writes the results, and they do not depend on N. As root, Open MPI\n"
    "needs OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 (and --oversubscribe\n"
    "for more ranks than cores). A crash leaves no half-written result file: finished runs\n"
    "are kept in <out>.checkpoint and `--resume` computes only the missing ones.";

}  // namespace rover::cli
