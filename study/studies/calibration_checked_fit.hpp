// The stages of a calibration fit, shared by the fit, the posterior and the
// experiment design (study/studies/calibration.hpp): the first search, the
// Gauss-Newton uncertainty at the optimum, the checked fit (integration
// check and profile probe) and the profile-likelihood intervals. Every
// function is collective over MPI ranks; results are rank 0's unless said.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/hdf5_file.hpp"
#include "study/estimators/least_squares_uncertainty.hpp"
#include "study/studies/calibration.hpp"
#include "study/studies/calibration_fit.hpp"
#include "study/studies/calibration_probe.hpp"

namespace rover::study {

// The Gauss-Newton uncertainty at the optimum. Parameters: the fitted ones
// (natural units) and, when it is profiled, the time offset (its derivative
// needs no simulation: the curve is shifted). Collective: the 2 p difference
// runs go through run_task_farm. `best` (values then offset) is rank 0's and
// is broadcast. Returns the uncertainty and its parameter names on rank 0.
struct GaussNewtonResult {
  bool ok = false;
  std::string message;
  std::vector<std::string> names;
  LeastSquaresUncertainty uncertainty;
  std::vector<double> noise_rms, noise_sd;  // per curve
  std::vector<double> weights;              // per curve: 1 / s_k (1 for one curve)
  Eigen::MatrixXd weighted_jacobian;
};
GaussNewtonResult gauss_newton_at_optimum(const CalibrationStudy& study, std::vector<double> best,
                                          const StudyRunOptions& control);

// The evaluations of a fit, as /history stores them (one row each: the p
// parameters, K offsets, pooled rms, objective, status), with the start each
// came from.
struct FitHistory {
  std::vector<double> rows, start;
  std::vector<std::string> messages;
};

// The columns of one /history row.
struct HistoryLayout {
  std::size_t parameters = 0, curves = 0;
  explicit HistoryLayout(const CalibrationStudy& s) : parameters(s.fit.size()), curves(s.datasets.size()) {}
  std::size_t rms() const { return parameters + curves; }  // after the parameters and the offsets
  std::size_t objective() const { return rms() + 1; }
  std::size_t status() const { return rms() + 2; }
  std::size_t width() const { return rms() + 3; }
};


// One evaluation of the objective: per dataset the offset, the pooled RMS,
// and the objective NLopt minimises (the RMS for one curve; for several,
// sum_k n_k log RMS_k / N, the profile likelihood with a noise sd per curve).
struct FitObjective {
  std::vector<double> offsets;
  double rms = 0.0, objective = 0.0;
  int status = 0;
};
FitObjective fit_objective(const CalibrationStudy& study, const std::vector<double>& values);

// The first search of an NLopt algorithm: one task per start (fanned out and
// checkpointed); returns the best point (values, then offsets) on rank 0.
std::vector<double> nlopt_search(const CalibrationStudy& study, const StudyRunOptions& control, const std::string& out,
                                 FitHistory& history);
// Appends the least-squares evaluations to the history (start index -1).
void append_history(const LeastSquaresCalibration& fit, FitHistory& history);

// The fit, its intervals and the integration check, tightening the
// integrator until its error moves no parameter by more than the check
// allows. Collective; the result is rank 0's.
struct CheckedFit {
  CalibrationStudy study;  // with the integrator the fit finally used
  LeastSquaresCalibration fit;
  GaussNewtonResult gn;
  IntegrationShift shift;
  ProfileProbe probe;
  std::vector<std::string> integrator_actions;
};

// Refits from a better point the profile probe found, at most.
inline constexpr int kMaxProbeRestarts = 5;

CheckedFit checked_fit(const CalibrationStudy& study, std::vector<double> start, const StudyRunOptions& control,
                       FitHistory& history);
// Whether the fit and its intervals exist on rank 0, for every rank.
bool fit_has_intervals(const CheckedFit& checked);
// The fit and its covariance (rank 0's) on every rank, as the profile probe takes them.
ProbeInput probe_input_on_every_rank(const CheckedFit& checked);

// Profile likelihood (Bates & Watts 1988, ch. 6; Venzon & Moolgavkar 1988):
// for each fitted parameter (a fitted time_offset excepted) a grid of
// `profile_points` values over +-4 Gauss-Newton standard errors around the
// optimum (the whole bounds when the se is not finite), clipped to the bounds;
// at each value the other parameters are re-optimised with BOBYQA (at most
// max_evaluations simulations) and the offsets profiled as in the fit. The
// profile is the weighted RSS sum_k RSS_k / s_k^2 (s_k: each curve's noise sd
// at the optimum), so the threshold is chi2_1(0.95) with unit variance.
// Collective: one task per grid point, fanned out with run_task_farm.
struct ParameterProfile {
  std::string name;
  std::vector<double> values, weighted_rss;
  ProfileInterval interval;
  bool complete = false;
};
std::vector<ParameterProfile> profile_parameters(const CalibrationStudy& study, const GaussNewtonResult& gn,
                                                 std::vector<double> best, const StudyRunOptions& control);

// The result of a fit (method optimize): the checked fit, every evaluation,
// the profiles, the fitted curves and whether its intervals can be trusted.
struct CalibrationFitResult {
  CheckedFit checked;
  FitHistory history;
  std::vector<ParameterProfile> profiles;
  std::vector<CalibrationCurve> fitted_curves;  // each curve at the best fit, in data time
  double best_rms_m = 0.0;                      // pooled over the curves
  std::vector<double> curve_rms_m;              // each curve's own, in the order of the datasets
  std::vector<double> curve_residual_lag1;      // each curve's residual lag-1 autocorrelation
  bool trusted = true;
  std::string not_valid_because;
};

// Collective. The result is complete on rank 0; the other ranks hold
// `trusted` only. `results_path` is where a first search checkpoints.
CalibrationFitResult run_calibration_fit(const CalibrationStudy& study, const StudyRunOptions& control,
                                         const std::string& results_path);
// Rank 0: the result file's datasets and attributes (not the provenance).
void write_calibration_fit(const CalibrationFitResult& fit, const CalibrationStudy& study, io::Hdf5Writer& h5);
// The console summary: convergence, the estimate, intervals, checks and warnings.
void report_calibration_fit(const CalibrationFitResult& fit, const CalibrationStudy& study, std::ostream& out);
// <stem>.png per curve (data and fit) and <stem>_profile_<name>.png per profile.
void plot_calibration_fit(const CalibrationFitResult& fit, const CalibrationStudy& study, const std::string& stem);

}  // namespace rover::study
