// The surrogate study: a sparse polynomial chaos expansion (Blatman & Sudret
// 2011) or a Gaussian process (Rasmussen & Williams 2006) of each QoI,
// trained on the runs of a design or of an existing result file
// (surrogate_training.hpp), validated by leave-one-out and, when given, on
// held-out runs, with the PCE's mean, variance and Sobol' indices in closed
// form (Sudret 2008) and their bootstrap intervals.
//
// load_surrogate_study() (surrogate_spec.hpp) reads the study;
// run_surrogate_study() makes or reads the runs and fits, printing nothing;
// write_surrogate_study(), report_surrogate_study() and plot_surrogate_study()
// (surrogate_report.hpp) put the result in HDF5, on a stream and in PNGs;
// surrogate_program() hands these to the study driver (study_driver.hpp).
//
// Failed runs are left out of the fit and counted. A QoI that is constant
// over the runs or non-finite in a successful run gets no indices (and, for a
// Gaussian process, no model); the reason is reported, never a NaN.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "study/studies/study_driver.hpp"
#include "study/studies/surrogate_file.hpp"
#include "study/studies/surrogate_spec.hpp"
#include "study/studies/surrogate_training.hpp"
#include "study/studies/pce_sensitivity.hpp"
#include "study/surrogate/pce_sobol.hpp"

namespace rover::study {

// The exit status of a surrogate study in which a QoI got no surrogate.
inline constexpr int kSomeQoiUnfittedStatus = 2;

struct SurrogateQoiResult {
  std::string name;
  int runs_used = 0;              // successful training runs
  bool fitted = false;            // a model exists (saved and predicted)
  std::string undefined_reason;   // why there is no model or, for a PCE, no indices
  FittedSurrogate model;
  // Polynomial chaos only.
  bool indices_defined = false;
  PceSobolIndices indices;
  bool has_intervals = false;
  PceSobolIntervals intervals;
  // Predicted against actual: leave-one-out at the training runs, the model at the held-out runs.
  Eigen::VectorXd actual, loo_predicted;
  Eigen::VectorXd held_out_actual, held_out_predicted;
};

struct SurrogateStudyResult {
  std::string results_path;
  TrainingRuns training;          // every training run, failed ones included
  TrainingRuns held_out;          // no runs when there is no held-out validation
  std::vector<SurrogateQoiResult> qoi;  // in the study's QoI order
  // Per channel of the study (polynomial chaos only): the curve's PCE on one
  // shared basis with mean(t), sd(t), S1_i(t), ST_i(t) and the
  // variance-weighted indices (pce_sensitivity.hpp), on the training runs.
  std::vector<PceChannelResult> channels;
  // From the "compare" file, per QoI of the study: its total indices in the
  // study's input order with their interval (empty where the file has none).
  struct ComparedIndices {
    Eigen::VectorXd ST, ST_lower, ST_upper;
  };
  std::vector<ComparedIndices> compared;
  SurrogateSet set;               // the fitted models and their inputs, as saved
  double runs_wall_time_s = 0.0, fit_wall_time_s = 0.0;
  std::vector<std::string> warnings;  // failed runs, low Q^2, undefined indices
};

// Fits every QoI on the successful training runs and scores it on the
// successful held-out runs where it is finite. No MPI, files or output. Throws io::ConfigError
// naming the source when fewer successful runs remain than the fit needs.
// When every run of the study's design failed, the result holds them and no
// model (each QoI unfitted, saying so): the driver keeps an earlier result
// and exits with kEveryRunFailedStatus, as for every study.
SurrogateStudyResult fit_surrogate_study(const SurrogateStudy& study, const TrainingRuns& training,
                                         const TrainingRuns& held_out);

// Collective over MPI ranks: the design's runs over the task farm, or the
// result files read on rank 0; then the fit on rank 0. The result is
// meaningful on rank 0 only.
SurrogateStudyResult run_surrogate_study(const SurrogateStudy& study, const StudyRuntime& runtime);

// The study as the driver runs it.
StudyProgram<SurrogateStudyResult> surrogate_program(SurrogateStudy study);

}  // namespace rover::study
