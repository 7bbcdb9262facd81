// Monte Carlo on the study core (paper Fig. 13d generalised): any uncertain
// parameters, any design, named QoIs and channels. For every channel, the band
// of the curves (mean, sd, mean -+ 3 sd, and the empirical 0.135 % / 99.865 %
// quantiles); for every QoI, its values and a summary with confidence
// intervals (mean: Student t; sd: bootstrap; quantiles: distribution-free,
// from order statistics, reported as missing when N is too small).
//
// Three parts: load_montecarlo_study() (config), MonteCarloAnalysis (compute:
// consumes run records in index order; pure, testable in-process) and
// run_montecarlo() (the runs over the MPI farm, streamed into the analysis and
// into the HDF5 file row by row; rank 0's memory does not grow with N beyond
// the QoI values).
//
// HDF5 (docs/results_format.md): /inputs/names, /inputs/values
// (N x d), /qoi/<name> (N), /summary/<qoi>/..., /t (T), /curves/<channel>
// (N x T, NaN for failed runs), /bands/<channel>/{mean,std,lower,upper,p00135,
// p99865}, /samples/{status,message,wall_time_s,rhs_evaluations}.
#pragma once

#include <string>
#include <vector>

#include "io/checkpoint.hpp"
#include "study/estimators/band_statistics.hpp"
#include "study/estimators/qoi_summary.hpp"
#include "study/estimators/streaming_band.hpp"
#include "study/studies/study_spec.hpp"

namespace rover::study {

struct MonteCarloStudy {
  StudySpec spec;
  double confidence = 0.95;
  int bootstrap_resamples = 1000;
};

MonteCarloStudy load_montecarlo_study(const std::string& path);

struct MonteCarloResult {
  int samples = 0, failed = 0;
  std::vector<std::vector<double>> qoi;        // [qoi][sample], NaN where a run failed
  std::vector<QoiSummary> summaries;           // [qoi]
  std::vector<Band> bands;                     // [channel]
  std::vector<int> status;                     // [sample]
  std::vector<std::string> messages;           // [sample]
  std::vector<double> wall_time_s, rhs_evaluations;  // [sample]
};

// Consumes the records of samples 0, 1, ..., N-1 in that order.
class MonteCarloAnalysis {
 public:
  MonteCarloAnalysis(const RecordLayout& layout, int samples, double confidence = 0.95,
                     int bootstrap_resamples = 1000, std::uint64_t seed = 1);
  void add(const RunRecord& record);
  MonteCarloResult finish() const;

 private:
  RecordLayout layout_;
  double confidence_;
  int bootstrap_resamples_;
  std::uint64_t seed_;
  MonteCarloResult result_;
  std::vector<StreamingBand> bands_;
};

struct StudyRunControl {
  std::string results_path;   // empty: results/<name>.h5
  bool resume = false;
  bool restart = false;  // discard a leftover checkpoint (the drivers refuse one without --resume or --restart)
  bool plot = true;
  int progress_interval_s = 5;
  std::string resume_command;
  io::CheckpointPolicy checkpoint;
};

// Collective over MPI ranks; rank 0 writes the HDF5 file and the PNGs.
// Returns the results path. Throws (rank 0) if every sample failed.
std::string run_montecarlo(const MonteCarloStudy& study, const StudyRunControl& control);

}  // namespace rover::study
