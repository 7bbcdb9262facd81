// Sobol' indices of the sensitivity study from a sparse polynomial chaos
// expansion ("method": "pce"): one PCE per QoI fitted on the runs of a
// space-filling design (LHS or Sobol'), the first-order and total indices in
// closed form from its coefficients with bootstrap confidence intervals, the
// leave-one-out Q^2 as its validation; per channel, a PCE of the curve on one
// shared basis and S_i(t), mean(t), sd(t) and the variance-weighted
// aggregated indices (Sudret 2008, "Global sensitivity analysis using
// polynomial chaos expansions", RESS 93; Blatman & Sudret 2011, "Adaptive
// sparse polynomial chaos expansion based on least angle regression", JCP 230).
//
// Study file keys (besides those of sensitivity.hpp):
//   "method": "pce",
//   "design": {"type": "latin_hypercube" | "lhs" | "sobol" | "monte_carlo", "samples": N, "seed": s},
//   "pce": {"max_degree": 12, "q_norm": 0.75, "bootstrap": 200, "q2_threshold": 0.95}
//
// Failed runs are left out (and counted). A QoI that is constant over the
// runs, or that has a non-finite value in a successful run, gets no indices:
// it is reported undefined with the reason, never as NaN, and the other QoIs
// keep theirs.
//
// HDF5 (the names of the pick-freeze results where they mean the same):
//   /indices/<qoi>/{S1,ST,S1_lower,S1_upper,ST_lower,ST_upper,mean,variance}
//     and, with the intervals, {S1,ST}_fixed_by_selection (d ints: 1 where
//     the selected terms fix the index at 0 or 1, so its interval says
//     nothing of the selection's uncertainty); group attributes: defined (0/1), undefined_reason, runs_used; on S1:
//     confidence, bootstrap_resamples, resamples_used. An undefined QoI has
//     no S1/ST (a constant one keeps its mean and zero variance).
//   /pce/<qoi>/{q2_loo, degree, terms, multi_indices (terms x d), coefficients}
//     attributes: q_norm, candidate_terms, runs, warning
//   /t, /indices_t/<channel>/{S1,ST (d x T), variance, mean, sd, q2_loo (T)},
//   /aggregated/<channel>/{S1,ST}; /pce_t/<channel>/{multi_indices, coefficients (terms x T)}
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "io/hdf5_file.hpp"
#include "io/json_reader.hpp"
#include "study/runtime/run_record.hpp"
#include "study/studies/study_output.hpp"
#include "study/studies/study_spec.hpp"
#include "study/surrogate/pce_curves.hpp"
#include "study/surrogate/pce_sobol.hpp"
#include "study/surrogate/polynomial_chaos.hpp"

namespace rover::study {

inline constexpr int kDefaultPceBootstrap = 200;
inline constexpr int kMaxPceBootstrap = 1000000;
inline constexpr int kMinPceBootstrap = 2;  // 0 turns the intervals off

struct PceSensitivityOptions {
  PolynomialChaosSettings settings;  // max_degree, q_norm, q2_threshold from the file
  int bootstrap = kDefaultPceBootstrap;
  double confidence = 0.95;
  std::uint64_t seed = 1;
};

// Reads the optional "pce" object of a study file; range errors name the file
// and the field (pce.max_degree, ...).
PceSensitivityOptions parse_pce_options(const io::JsonReader& r, double confidence, std::uint64_t seed);

// The fewest runs the fit accepts for these inputs and settings.
int min_pce_sensitivity_runs(const StudySpec& spec, const PceSensitivityOptions& options);

// Indices of one QoI. When !indices.defined, `undefined_reason` says why and
// no expansion or intervals were computed (fit_done false).
struct PceQoiResult {
  std::string name;
  int runs_used = 0;                 // successful runs the PCE was fitted on
  bool fit_done = false;
  PolynomialChaosExpansion expansion;
  PceSobolIndices indices;
  bool has_intervals = false;
  PceSobolIntervals intervals;
  std::string undefined_reason;      // empty when the indices are defined
};

struct PceChannelResult {
  std::string name;
  bool defined = false;
  std::string undefined_reason;
  PolynomialChaosCurves curves;
  CurveSobolIndices indices;
};

struct PceSensitivityResult {
  std::vector<PceQoiResult> qoi;          // one per QoI, in the model's order
  std::vector<PceChannelResult> channels; // one per channel
  int runs_used = 0;                      // successful runs
  std::vector<std::string> warnings;      // Q^2 below the threshold, undefined indices
};

// One QoI's PCE and indices from the successful runs (x_ok rows) and their
// values. Never throws for a constant or non-finite y: the result says why
// the indices are undefined.
PceQoiResult pce_qoi_indices(const std::string& name, const DesignMatrix& x_ok, const Eigen::VectorXd& y_ok,
                             const std::vector<Distribution>& inputs, const PceSensitivityOptions& options);

// Bootstrap intervals whose index the selected terms fix at 0 or 1
// (pce_indices_fixed_by_selection): the interval text of index i, "[lo, hi]"
// or kFixedBySelectionText; the note that explains that text under a table
// that shows it (empty when none); and, when the expansion validates below
// q2_threshold, a warning naming those indices (else empty).
inline constexpr const char* kFixedBySelectionText = "fixed by terms";
// <group>S1_fixed_by_selection and <group>ST_fixed_by_selection: 1 where fixed, else 0.
void write_pce_fixed_by_selection(io::Hdf5Writer& h5, const std::string& group, const PceSobolIntervals& intervals);
std::string pce_interval_text(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                              const std::vector<bool>& fixed, Eigen::Index i);
std::string pce_fixed_by_selection_note(const PceSobolIntervals& intervals);
std::string pce_fixed_by_selection_warning(const std::string& qoi, const PceSobolIntervals& intervals,
                                           const std::vector<std::string>& labels, double q2_loo,
                                           double q2_threshold);

// Whether some QoI's indices come from an expansion not to be trusted (worse
// than the mean of its runs, or too many terms for its runs:
// surrogate_not_to_trust), or are undefined although the
// QoI varies (no term beyond the constant was selected): the warnings say so.
bool pce_indices_not_to_trust(const PceSensitivityResult& result);

// One channel's curve PCE and indices along time from the successful runs
// (x_ok rows) and their curves (runs x time samples). Never throws: the
// result says why the indices are undefined.
PceChannelResult pce_channel_indices(const std::string& name, const DesignMatrix& x_ok, const Eigen::MatrixXd& y_ok,
                                     const std::vector<Distribution>& inputs, const PceSensitivityOptions& options);
// /indices_t/<channel>/..., /aggregated/<channel>/... and /pce_t/<channel>/... (layout above).
void write_pce_channel(io::Hdf5Writer& h5, const PceChannelResult& channel);
// S1(t) and ST(t) of the inputs that matter, one PNG; labels: one per input;
// `command` labels the line that says it was written ("sensitivity", "surrogate").
void plot_pce_channel(const std::string& png, const PceChannelResult& channel, const std::vector<double>& t,
                      const std::vector<std::string>& labels, const std::string& command);

// Every QoI and channel from the run records (in run order; failed runs are
// left out). Prints nothing.
PceSensitivityResult analyse_pce_sensitivity(const StudySpec& spec, const PceSensitivityOptions& options,
                                             const DesignMatrix& x, const std::vector<RunRecord>& records);

void write_pce_sensitivity(io::Hdf5Writer& h5, const StudySpec& spec, const PceSensitivityOptions& options,
                           const PceSensitivityResult& result);
// Table of S1 and ST with intervals and Q^2 per QoI, aggregated channel indices.
void print_pce_sensitivity(std::ostream& out, const StudySpec& spec, const PceSensitivityOptions& options,
                           const PceSensitivityResult& result);
// <results>_pce_<qoi>.png bar charts and <results>_pce_t_<channel>.png.
// pce_sensitivity_figures: `figures` with those of plot_pce_sensitivity added.
std::vector<PlannedFigure> pce_sensitivity_figures(const StudySpec& spec, std::vector<PlannedFigure> figures);
void plot_pce_sensitivity(const std::string& results_path, const StudySpec& spec,
                          const PceSensitivityResult& result);

}  // namespace rover::study
