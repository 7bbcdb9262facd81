// Monte Carlo on the study core (paper Fig. 13d generalised): any uncertain
// parameters, any design, named QoIs and channels. For every channel, the band
// of the curves (mean, sd, mean -+ 3 sd, and the empirical 0.135 % / 99.865 %
// quantiles); for every QoI, its values and a summary with confidence
// intervals (mean: Student t; sd: bootstrap; quantiles: distribution-free,
// from order statistics, reported as missing when N is too small).
//
// The study's parts, run by the study driver (study_driver.hpp):
// load_montecarlo_study() (config), run_montecarlo() (the runs over the MPI
// farm, streamed into MonteCarloAnalysis and into the result file row by row,
// so rank 0's memory does not grow with N beyond the QoI values),
// write_montecarlo(), report_montecarlo() and plot_montecarlo().
//
// HDF5 (docs/results_format.md): /inputs/names, /inputs/values
// (N x d), /qoi/<name> (N), /summary/<qoi>/..., /t (T), /curves/<channel>
// (N x T, NaN for failed runs), /bands/<channel>/{mean,std,lower,upper,p00135,
// p99865}, /samples/{status,message,wall_time_s,rhs_evaluations}.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "io/hdf5_file.hpp"
#include "study/estimators/band_statistics.hpp"
#include "study/estimators/qoi_summary.hpp"
#include "study/estimators/streaming_band.hpp"
#include "study/studies/study_driver.hpp"
#include "study/studies/study_spec.hpp"

namespace rover::study {

struct MonteCarloStudy {
  StudySpec spec;
  double confidence = 0.95;
  int bootstrap_resamples = 1000;
};

MonteCarloStudy load_montecarlo_study(const std::string& path, const DesignOverrides& overrides = {});

struct MonteCarloResult {
  int samples = 0, failed = 0;
  std::vector<std::vector<double>> qoi;        // [qoi][sample], NaN where a run failed
  std::vector<QoiSummary> summaries;           // [qoi]
  std::vector<Band> bands;                     // [channel]
  std::vector<int> status;                     // [sample]
  std::vector<std::string> messages;           // [sample]
  std::vector<double> wall_time_s, rhs_evaluations;  // [sample]
  // Set by run_montecarlo(): what the result belongs to.
  MonteCarloStudy study;
  DesignMatrix inputs;                         // the design, samples x inputs
};

// Consumes the records of samples 0, 1, ..., N-1 in that order.
class MonteCarloAnalysis {
 public:
  MonteCarloAnalysis(const RecordLayout& layout, int samples, double confidence = 0.95,
                     int bootstrap_resamples = 1000, std::uint64_t seed = 1);
  void add(const RunRecord& record);
  // Once, after the last add(): the result takes the per-run vectors over.
  MonteCarloResult finish();

 private:
  RecordLayout layout_;
  double confidence_;
  int bootstrap_resamples_;
  std::uint64_t seed_;
  MonteCarloResult result_;
  std::vector<StreamingBand> bands_;
};

// The bytes rank 0 holds: the design on every rank, the QoIs, statuses and
// band heaps on rank 0.
MemoryEstimate montecarlo_memory(const MonteCarloStudy& study);

// Collective over MPI ranks; on rank 0 the curves go into runtime.h5 as the
// runs arrive. The result is meaningful on rank 0.
MonteCarloResult run_montecarlo(const MonteCarloStudy& study, const StudyRuntime& runtime);

void write_montecarlo(const MonteCarloResult& result, io::Hdf5Writer& h5);
// Per QoI: mean and sd with their intervals, and the quantiles' note.
void report_montecarlo(const MonteCarloResult& result, std::ostream& out);
// <results>_summary.png (each channel's band, each QoI's histogram and
// running mean); with PlotSelection::kAll also <results>_band_<channel>.png,
// <results>_hist_<qoi>.png and <results>_convergence_<qoi>_{mean,sd}.png.
void plot_montecarlo(const MonteCarloResult& result, const std::string& results_path, PlotSelection plots);
// The figures plot_montecarlo writes with `plots`, one entry per file.
std::vector<PlannedFigure> montecarlo_figures(const MonteCarloStudy& study, PlotSelection plots);

// The study as the driver runs it.
StudyProgram<MonteCarloResult> montecarlo_program(MonteCarloStudy study);

}  // namespace rover::study
