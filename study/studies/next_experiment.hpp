// Which drop to do next: candidate experiments ranked by the 95 % interval
// each fitted parameter is expected to have once that experiment's curve is
// added to the data (docs/model.md §8 for the channels).
//
// At the current estimate theta (the checked fit of the calibration study),
// the data hold the Fisher information I_0 = J_w^T J_w / s^2 about the
// fitted parameters and the curves' offsets (J_w the weighted residual
// Jacobian, s the noise sd of the weighted residuals). A candidate curve of
// noise sd sigma on its time grid adds J_c^T J_c / sigma^2, J_c its Jacobian
// at theta with respect to the fitted parameters and its own time offset (a
// new nuisance parameter). The expected covariance is the inverse of the sum;
// its diagonal gives each parameter's expected 95 % half-width, z_0.975 sd
// (the linear approximation of Bates & Watts 1988, section 2.3, applied
// before the data exist: an optimal-design criterion, Atkinson, Donev &
// Tobias 2007, ch. 10). Candidates are ranked by the geometric mean over the
// fitted parameters of expected / current half-width (a D-optimality-like
// score per parameter).
//
// Candidate file (JSON):
//   {"description": "...",                                  (optional)
//    "candidates": [
//     {"name": "drop from 0.35 m, B_l z at 1 kHz",        (default "candidate i")
//      "scenario": "../scenarios/drop_horizontal.json",   (relative to this file)
//      "channel": "B_l_z", "rate_hz": 1000, "noise_sd": 5e-5,
//      "set": {"scenario.initial_q.z": 0.35, "scenario.initial_q.chi": 0.05}}]}
// "set" changes any parameter of the candidate's scenario or rover by name
// (study/model/parameter_space.hpp), as a drop height or skew.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/hdf5_file.hpp"
#include "study/studies/calibration.hpp"
#include "study/studies/study_driver.hpp"

namespace rover::study {

struct NextExperimentCandidate {
  std::string name, scenario_path, channel = "B_l_z";
  double rate_hz = 0, noise_sd_m = 0;
  io::ScenarioSources sources;  // with "set" applied
};

// Throws io::ConfigError naming the file, the field and the value.
std::vector<NextExperimentCandidate> load_next_experiment_candidates(const std::string& path,
                                                                     const CalibrationStudy& study);

struct NextExperimentRanking {
  bool ok = false;
  std::string message;  // why there is no ranking
  std::vector<std::string> parameters;        // the fitted parameters
  Eigen::VectorXd current_half_width;         // 95 %, per parameter
  std::vector<std::string> candidates;        // in rank order
  Eigen::MatrixXd expected_half_width;        // candidates x parameters, rank order
  Eigen::VectorXd score;                      // geometric mean of expected / current
  std::vector<double> estimate;               // theta the ranking is computed at
  // Rank 0: whether the fit it is computed at is one the fit alone would
  // trust; a ranking at an untrusted fit is written flagged, exit status 2.
  bool fit_trusted = false;
  std::string not_valid_because;  // the fit's, as the fit alone says it
};

// Collective over MPI ranks (the fit and the candidates' Jacobians); the
// ranking is rank 0's.
NextExperimentRanking rank_next_experiments(const CalibrationStudy& study,
                                            const std::vector<NextExperimentCandidate>& candidates,
                                            const StudyRunOptions& control);

// The ranking as a program of the study driver: the candidates are loaded
// (and refused) before any run; it writes the table to results/<study
// name>_next_experiment.h5 by default, and asks for kUntrustedStatus when
// there is no ranking (the fit has no intervals, or a candidate cannot be
// simulated at the estimate; an earlier file at the results path is then
// kept) or the fit it is computed at is not trusted.
StudyProgram<NextExperimentRanking> next_experiment_program(CalibrationStudy study, const std::string& candidates_path);

// Rank 0: /next_experiment (attributes ranked and, without a ranking,
// not_ranked_because; with one, ranking_valid and not_valid_because).
void write_next_experiment(const NextExperimentRanking& ranking, io::Hdf5Writer& h5);
void report_next_experiment(const NextExperimentRanking& ranking, std::ostream& out);

}  // namespace rover::study
