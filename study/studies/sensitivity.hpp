// Global sensitivity analysis on the study core: variance-based Sobol' indices
// (pick-freeze design, Saltelli 2010 first-order and Jansen 1999 total
// estimators, bootstrap confidence intervals) for every QoI and along time for
// every channel, and Morris (1991) elementary-effects screening. The rover and
// the analytic test models (study_model.hpp) run through the same code.
//
// Study file (the keys of study_spec.hpp, with):
//   "type": "sensitivity", "method": "sobol" | "morris" | "pce" (pce_sensitivity.hpp),
//   "design": sobol:  {"type": "sobol" | "monte_carlo", "samples": N, "seed": s}  (base matrices)
//             morris: {"trajectories": r, "levels": p, "seed": s}
//             pce:    {"type": "latin_hypercube" | "lhs" | "sobol" | "monte_carlo", "samples": N, "seed": s}
//   "second_order": false, "estimator": "saltelli_jansen" | "martinez",
//   "bootstrap": 1000, "confidence": 0.95,
//   "max_failed_fraction": 0.05   (more failed pick-freeze groups or trajectories: the study fails)
//
// Failed runs never enter an index: a failed run drops its whole pick-freeze
// group (A, B and every A_B^(i) of that row) or its Morris trajectory, and the
// result says how many and where in input space.
//
// HDF5: /inputs/{names,values}, /qoi/<name>, /samples/{status,message};
// sobol: /indices/<qoi>/{S1,ST,S1_lower,S1_upper,ST_lower,ST_upper,mean,variance}
// (+ S2, S2_lower, S2_upper, d x d), /indices_t/<channel>/{S1,ST} (d x T),
// /indices_t/<channel>/variance (T), /aggregated/<channel>/{S1,ST}, /t;
// morris: /morris/<qoi>/{mu,mu_star,sigma,mu_star_lower,mu_star_upper,ranking};
// pce: the same /indices, /indices_t and /aggregated names, plus /pce/<qoi>
// (pce_sensitivity.hpp). A failed run is left out of a PCE alone.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "io/hdf5_file.hpp"
#include "study/estimators/morris.hpp"
#include "study/estimators/sobol_indices.hpp"
#include "study/studies/pce_sensitivity.hpp"
#include "study/studies/study_driver.hpp"
#include "study/studies/study_spec.hpp"

namespace rover::study {

enum class SensitivityMethod { kSobol, kMorris, kPce };

// "sobol", "morris", "pce".
const char* sensitivity_method_name(SensitivityMethod method);

struct SensitivityStudy {
  StudySpec spec;
  SensitivityMethod method = SensitivityMethod::kSobol;
  // Sobol'
  PickFreezeLayout layout;
  SobolOptions sobol;
  // Morris
  int trajectories = 0, levels = 4;
  MorrisOptions morris;
  // Polynomial chaos
  PceSensitivityOptions pce;
  double max_failed_fraction = 0.05;
};

// The exit status of a study whose every QoI and channel has its indices
// undefined for want of runs (too few whole groups or trajectories): a
// result not to use. A QoI that is constant has an answer (no input moves it).
inline constexpr int kNoIndicesStatus = 2;

// Reads and checks a study file; errors are io::ConfigErrors naming the file
// and the field. `overrides.samples` (--samples) sets the Sobol' base sample
// count or the PCE runs before they are checked (std::invalid_argument naming
// the flag when too few; a Morris study refuses it).
SensitivityStudy load_sensitivity_study(const std::string& path, const DesignOverrides& overrides = {});


// The runs of the study in physical units (rows in run order).
DesignMatrix sensitivity_design(const SensitivityStudy& study);

// A QoI whose indices are undefined (a constant QoI), or a channel whose
// indices along time are (a channel that does not vary), and why.
struct UndefinedIndices {
  std::string qoi, reason;  // qoi: the QoI's or the channel's name
};

struct SensitivityResult {
  std::vector<SobolIndices> sobol;                 // [qoi]; empty vectors where undefined
  std::vector<SobolIndicesAlongTime> sobol_t;      // [channel]
  std::vector<MorrisResult> morris;                // [qoi]; empty vectors where undefined
  std::vector<UndefinedIndices> undefined;         // Sobol' and Morris QoIs without indices
  // Fewer whole pick-freeze groups or trajectories than the indices need
  // (every QoI's are then undefined for want of runs, not for being constant).
  bool too_few_whole_units = false;
  PceSensitivityResult pce;                        // method pce only
  std::vector<std::vector<double>> qoi;            // [qoi][run]
  std::vector<int> status;                         // [run]
  std::vector<std::string> messages;               // [run]
  int failed_runs = 0;
  std::string failure_report;                      // where in input space runs failed
  std::vector<std::string> warnings;               // intervals too wide, S1 sum above 1, ...
  // Set by run_sensitivity(): what the result belongs to, and its timings.
  SensitivityStudy study;
  DesignMatrix inputs;                             // the runs' inputs, in run order
  double runs_wall_time_s = 0.0, analysis_wall_time_s = 0.0;
};

// Whether every Sobol' or Morris QoI and every channel of `result` has its
// indices undefined because too few whole units came through (a PCE result
// has no undefined ones).
bool no_index_for_want_of_runs(const SensitivityResult& result);

// Compute: the indices from the records of every run, in run order (in-process,
// testable without MPI or files). Throws std::runtime_error when more than
// max_failed_fraction of the groups or trajectories failed. A QoI that is
// constant over the successful runs has no indices: it is named in
// `undefined` (and in the warnings), and the other QoIs' indices are kept.
SensitivityResult analyse_sensitivity(const SensitivityStudy& study, const DesignMatrix& x,
                                      const std::vector<RunRecord>& records);

// The bytes rank 0 holds: every run's record until the indices are estimated.
MemoryEstimate sensitivity_memory(const SensitivityStudy& study);

// Collective over MPI ranks: the runs, then (rank 0) analyse_sensitivity().
// The result is meaningful on rank 0.
SensitivityResult run_sensitivity(const SensitivityStudy& study, const StudyRuntime& runtime);

void write_sensitivity(const SensitivityResult& result, io::Hdf5Writer& h5);
// Where runs failed, the indices ranked per QoI, the aggregated indices per
// channel, and the warnings.
void report_sensitivity(const SensitivityResult& result, std::ostream& out);
// <results>_summary.png (S1 and ST per QoI, indices along time per channel,
// or the Morris planes); with PlotSelection::kAll also
// <results>_sobol_<qoi>.png, <results>_sobol_t_<channel>.png (and
// _variance.png), <results>_morris_<qoi>.png, or the PCE's figures
// (plot_pce_sensitivity).
void plot_sensitivity(const SensitivityResult& result, const std::string& results_path, PlotSelection plots);
// The figures plot_sensitivity writes with `plots`, one entry per file.
std::vector<PlannedFigure> sensitivity_figures(const SensitivityStudy& study, PlotSelection plots);

// The study as the driver runs it.
StudyProgram<SensitivityResult> sensitivity_program(SensitivityStudy study);

}  // namespace rover::study
