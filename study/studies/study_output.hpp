// What every study writes the same way: where results go (checked before the
// first run), file names beside the result file, the provenance attributes, and
// the design's inputs.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "io/hdf5_file.hpp"
#include "io/process_memory.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/study_spec.hpp"

namespace rover::study {

// The result file: `requested`, or results/<name>.h5. Throws
// std::invalid_argument before any run if it names a directory, does not end
// in .h5 (or .csv, when `csv_allowed`), or its directory cannot be created;
// the message names --out, or the default path when no --out was given
// (`requested` empty, or a command's own default: `requested_is_default`).
std::string checked_results_path(const std::string& name, const std::string& requested, bool csv_allowed = false,
                                 bool requested_is_default = false);

// How messages name the result path: "--out 'r.h5'", or "the default output
// 'results/x.h5'" when no --out was given.
std::string results_path_label(const std::string& path, bool is_default);

// Refuses up front, with the estimate, a study whose rank-0 working set would
// exceed `limit` (io/process_memory.hpp): "would hold 12.3 GB of run records
// (...) in memory, more than the 4 GB of ...". `what` says what the bytes are.
void require_memory(const std::string& what, double bytes,
                    const io::MemoryLimit& limit = io::process_memory_limit());

// "results/x.h5" + "_band_B_l_z.png" -> "results/x_band_B_l_z.png".
std::string sibling_path(const std::string& results_path, const std::string& suffix);

// A figure a study writes beside its result: <stem><suffix> (sibling_path),
// and what it shows ("the Sobol' indices of QoI 't_B_l_z'").
struct PlannedFigure {
  std::string suffix;
  std::string shows;
};

// The figures every selection but "none" draws: the summary alone. A study
// that draws more with --plots all adds its own after it.
std::vector<PlannedFigure> summary_figure(PlotSelection plots);

// Empty when the figures have distinct file names; else, for every two that
// share one, "the figures of <one> and of <other> would both be written to
// <path>", joined by "; ".
std::string shared_figure_names(const std::string& results_path, const std::vector<PlannedFigure>& figures);

// The root attributes of the integrator that made a result's runs: integrator
// (its name) and the settings it ran with: rtol, atol and slip_tol for the
// methods that choose their own steps, fixed_step_s for rk4.
void write_integrator_provenance(io::Hdf5Writer& h5, const IntegratorSettings& integrator);

// The integrator a result file records (write_integrator_provenance), or none
// when it records no integrator or one of no version of rover. An rk4 file
// without fixed_step_s (written before the step was recorded) gives a NaN
// fixed step: not known.
std::optional<IntegratorSettings> recorded_integrator(const io::Hdf5Reader& h5);

// The root attributes every study result carries: study (its type), name,
// study_file, study_json (the file's text), the integrator's
// (write_integrator_provenance, when a scenario is simulated: `integrator`
// not null), ranks, fingerprint, project_version.
void write_base_provenance(io::Hdf5Writer& h5, const std::string& type, const std::string& name,
                           const std::string& study_path, const IntegratorSettings* integrator,
                           const std::string& fingerprint);

// Root attributes: study (type), name, description, study_file, study_json,
// scenario / model, the integrator's, ranks, fingerprint, project_version.
// `runs_integrator`, when given, is recorded instead of the spec's: the
// integrator that made runs the study read from a file.
void write_study_provenance(io::Hdf5Writer& h5, const StudySpec& spec, const std::string& fingerprint,
                            const IntegratorSettings* runs_integrator = nullptr);

// /inputs/names (d), /inputs/labels (d), /inputs/distributions (d, described)
// and /inputs/values (N x d).
// What the study's runs are, for its banner: "scenario drop (path) on
// rosenbrock at rtol 1e-05, atol 3e-06, slip_tol 0.01, which \"accuracy\"
// chose"; an analytic model's name.
std::string runs_description(const StudySpec& spec);

void write_study_inputs(io::Hdf5Writer& h5, const StudySpec& spec, const DesignMatrix& x);
// The definition (qoi_definition) of each QoI of `qois` as an attribute of
// its values, <prefix>/qoi/<name>, written already: a study trained on the
// file later checks that its QoIs of those names are the same.
void write_qoi_definitions(io::Hdf5Writer& h5, const std::vector<QoiSpec>& qois, const std::string& prefix = "");
// The root attribute undefined_indices, "t_min, at_rest": the QoIs that have
// no sensitivity indices (constant over the runs); nothing when none.
void write_undefined_indices(io::Hdf5Writer& h5, const std::vector<std::string>& qois);

}  // namespace rover::study
