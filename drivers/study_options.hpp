// Options shared by the study subcommands (montecarlo, surface, calibrate).
#pragma once

#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "drivers/options.hpp"
#include "study/studies/montecarlo.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::cli {

inline void add_study_control(CLI::App& app, study::StudyRunControl& c) {
  app.add_option("--out", c.results_path, "HDF5 result file (default results/<study name>.h5)");
  app.add_flag("--resume", c.resume,
               "Continue an interrupted study from its checkpoint (<out>.checkpoint): only the "
               "missing runs are computed");
  app.add_flag("!--no-plot", c.plot, "Do not write PNG plots");
  app.add_option("--progress-interval", c.progress_interval_s, "Seconds between progress lines")
      ->capture_default_str()->check(CLI::Range(1, 86400));
  app.add_option("--checkpoint-every", c.checkpoint.every_records,
                 "Flush finished runs to <out>.checkpoint after this many (or every 60 s)")
      ->capture_default_str()->check(CLI::Range(1, 1000000));
}

// The checks of a study's --out (a file, in a directory that can be made, not
// the study file itself), before the study is loaded.
inline void check_study_output(FlagChecks& checks, const study::StudyRunControl& c, const std::string& study_path) {
  checks.output_file("--out", c.results_path, /*regular_only=*/true);
  checks.distinct_files("--out", c.results_path, "--study", study_path);
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

// Runs a study inside the command's MPI session and reports an interrupt
// there (exit status 130): after a Ctrl-C of mpirun, MPI_Finalize does not
// return before Open MPI kills the rank, so a message printed after the
// session ended would be lost.
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
