// The outputs of a surrogate study (surrogate_study.hpp): the HDF5 result,
// the console report and the PNGs.
//
// HDF5 (docs/results_format.md, "surrogate"): the provenance attributes of
// every study and surrogate, training, runs, failed_runs, held_out_runs,
// held_out_source, runs_wall_time_s, fit_wall_time_s; the training runs as a
// study writes them (/inputs/..., /qoi/<name>, /samples/{status,message}), so
// the file can train another surrogate; the saved models (/surrogate,
// surrogate_file.hpp); per QoI /validation/<qoi>/{actual, loo_predicted,
// held_out_actual, held_out_predicted} and, for a PCE,
// /indices/<qoi>/{mean, variance, S1, ST, S1_lower, S1_upper, ST_lower,
// ST_upper} with group attributes defined, undefined_reason, runs_used.
//
// PNGs beside the result: <out>_surrogate.png (predicted against actual per
// QoI, Q^2 in each title) and, for a PCE, <out>_surrogate_indices.png (total
// indices with their bootstrap intervals, per QoI).
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "io/hdf5_file.hpp"
#include "study/studies/surrogate_study.hpp"

namespace rover::study {

void write_surrogate_study(io::Hdf5Writer& h5, const SurrogateStudy& study, const SurrogateStudyResult& result);

// Per QoI: the model, its validation, mean and sd, and (PCE) S1 and ST with
// intervals by decreasing total index; then the warnings.
void report_surrogate_study(std::ostream& out, const SurrogateStudy& study, const SurrogateStudyResult& result);

// Writes the PNGs beside result.results_path; a missing gnuplot is a warning on `log`.
// The figures plot_surrogate_study may write, one entry per file.
std::vector<PlannedFigure> surrogate_figures(const SurrogateStudy& study);
void plot_surrogate_study(const SurrogateStudy& study, const SurrogateStudyResult& result, std::ostream& log);

}  // namespace rover::study
