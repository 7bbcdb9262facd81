// The runs a surrogate is trained and validated on: the study's design run now
// over the MPI task farm, or the runs of an existing result file of
// montecarlo, evaluate, sensitivity or surrogate (docs/results_format.md):
// /inputs/names and /inputs/values (runs x inputs), /qoi/<name> (runs) and,
// when present, /samples/status (0 = ok). Failed runs keep their rows, with
// their status and NaN values, so that they are counted and reported; the fit
// leaves them out.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "study/studies/montecarlo.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/surrogate_spec.hpp"

namespace rover::study {

struct TrainingRuns {
  std::string source;             // "design" or the result file
  DesignMatrix x;                 // runs x inputs, in the study's input order
  Eigen::MatrixXd y;              // runs x QoIs, in the study's QoI order; NaN where a run failed
  std::vector<int> status;        // per run, run_status (0 ok)
  std::vector<std::string> messages;
  // Per channel of the study: runs x time samples, NaN where a run failed
  // (a design's runs only).
  std::vector<Eigen::MatrixXd> curves;
  // Non-empty when the file records no scenario or rover config (a file of
  // an earlier version): why its runs could not be checked against the study's.
  std::string unchecked_provenance;
  // The integrator the file records its runs were made with (none for a
  // design's runs, which use the study's).
  std::optional<IntegratorSettings> integrator;

  int runs() const { return static_cast<int>(x.rows()); }
  int failed_runs() const;
  // The runs first .. first + count - 1.
  TrainingRuns slice(int first, int count) const;
};

// Two runs are one run when every input differs by at most this share of
// its span over the training runs (of its magnitude where it does not vary):
// a surrogate cannot tell them apart, so a copy validates nothing.
inline constexpr double kSameRunRelativeDistance = 1e-6;

// An input a file's runs hold at one value, and that the study does not
// list, is the study's nominal value when the two differ by at most this
// share of their magnitude: values written as text of 10 or more significant
// digits and read back agree, another rover's do not.
inline constexpr double kHeldInputRelativeTolerance = 1e-9;

// Empty unless runs of a file were made with another integrator than the
// study's or than the training runs': then what differs and what it means.
std::string integrator_mismatch(const SurrogateStudy& study, const TrainingRuns& training,
                                const TrainingRuns& held_out);

// How many runs have the inputs of an earlier run (in sorted order), equal
// within kSameRunRelativeDistance.
long long repeated_runs(const TrainingRuns& runs);

// Empty unless held-out runs repeat training runs (inputs equal within
// kSameRunRelativeDistance); then how many, and the first pair.
std::string shared_runs(const TrainingRuns& training, const TrainingRuns& held_out);

// Reads the runs of a result file for the study's inputs and QoIs. Columns
// are matched by parameter name (/inputs/names) in any order; `role` says
// what the file is for in messages ("training", "held-out"). Throws
// io::ConfigError naming the file for: no /inputs/names or /inputs/values, an
// input of the study missing, an input the study does not list that varies
// over the runs or, on the rover, is held at another value than the study's
// scenario and rover give it (kHeldInputRelativeTolerance), a QoI missing (listing those present), sizes that disagree,
// or an input value outside its distribution's support (naming the run).
TrainingRuns read_result_runs(const std::string& path, const SurrogateStudy& study, const std::string& role);

// Throws io::ConfigError naming the file and `role` if the result file
// records a scenario or rover config other than the study's; returns a note
// for the study's warnings if it records none (its runs cannot be checked),
// else nothing.
std::string check_result_provenance(const std::string& path, const SurrogateStudy& study, const std::string& role);

// Collective over MPI ranks: runs the study's design over the task farm with
// the driver's options (checkpointed beside the result, --resume as the
// other studies). The runs on rank 0; empty on the other ranks.
TrainingRuns run_design_runs(const SurrogateStudy& study, const StudyRunOptions& options);

}  // namespace rover::study
