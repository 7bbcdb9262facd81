// The least-squares fit of a calibration (docs/model.md §8 for the measured
// channels): Levenberg-Marquardt on the residual vector of every curve, the
// time offsets among its parameters, the Jacobian a finite difference fanned
// out over MPI ranks; then the check that the integrator's error is below
// what the data resolve.
//
// Parameters of the iterations: the simulated fitted parameters (log10 for a
// log-scale one) and one time offset per curve (a fitted "time_offset" is the
// single curve's offset). The offsets start at their profiled best (a scan of
// the offset range) and move with the others; their Jacobian columns need no
// simulation (the curve is shifted). With several curves the objective is the
// profile likelihood sum_k n_k log RSS_k; it is minimised by rounds of
// weighted least squares with weights 1 / RMS_k from the previous round (the
// stationary points agree: the gradients do), until the weights settle.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "study/estimators/levenberg_marquardt.hpp"
#include "study/studies/calibration.hpp"

namespace rover::study {

// Jacobian of the residuals of every curve (rows curve by curve) in natural
// units: columns the fitted parameters in the order of study.fit, then (when
// the offsets are profiled) one column per curve's offset. Collective: the
// 2 p difference runs go through the task farm; every rank gets the result.
struct CalibrationJacobian {
  bool ok = false;
  std::string message;
  Eigen::MatrixXd jacobian;
  Eigen::VectorXd residuals;  // at the point itself, unweighted
};
CalibrationJacobian calibration_jacobian(const CalibrationStudy& study, const std::vector<double>& values,
                                         const std::vector<double>& offsets, int progress_interval_s);

// Every residual evaluation of the fit, as /history stores it.
struct CalibrationEvaluation {
  std::vector<double> values, offsets;
  double rms_m = 0, objective = 0;
  int status = 0;  // 0 ok, 1 a simulation failed
};

struct LeastSquaresCalibration {
  std::vector<double> values;   // natural units, order of study.fit
  std::vector<double> offsets;  // per curve [s]
  LeastSquaresStop stop = LeastSquaresStop::kMaxIterations;
  bool converged = false;
  std::string message;  // why it stopped, in words
  int iterations = 0;
  std::vector<CalibrationEvaluation> history;
};

// Collective; every rank returns the same fit. `start`: natural values in the
// order of study.fit.
LeastSquaresCalibration least_squares_calibration(const CalibrationStudy& study, const std::vector<double>& start,
                                                  int progress_interval_s);

// The shift of each fitted parameter, in its standard errors, that running
// the best curves on `reference` instead of the study's integrator causes:
// one Gauss-Newton step on the residual difference (weighted as the fit).
// `jacobian` and `standard_error` as gauss_newton_uncertainty gives them.
struct IntegrationShift {
  bool ok = false;
  std::string message;
  std::vector<double> shift_se;  // per fitted parameter
  std::vector<double> step;      // per fitted parameter, natural units: the reference's optimum less ours
  double largest_se = 0;         // max |shift_se|
};
IntegrationShift integration_shift(const CalibrationStudy& study, const std::vector<double>& values,
                                   const std::vector<double>& offsets, const std::vector<double>& weights,
                                   const Eigen::MatrixXd& weighted_jacobian, const Eigen::VectorXd& standard_error);

// The fit of a study as the experiment design needs it: the fit the study
// alone would run (its first search, the checked fit; no profiles), the
// estimate, its verdict, and the information the data hold about it
// (weighted Jacobian and the noise sd of the weighted residuals). Collective;
// the Jacobian and the verdict are rank 0's, the rest every rank's.
struct CalibrationEstimate {
  CalibrationStudy study;       // on the integrator the check proved sufficient
  std::vector<double> values;   // order of study.fit
  std::vector<double> offsets;  // per curve
  bool valid = false;           // converged, with intervals: there is information to rank with
  std::string why_not;
  bool trusted = false;            // the fit alone would trust its intervals (exit 0)
  std::string not_valid_because;   // why not, as the fit alone says it
  std::vector<std::string> names;     // the Jacobian's columns
  Eigen::MatrixXd weighted_jacobian;  // rows weighted by 1 / RMS_k (1 for one curve)
  std::vector<double> weights;        // per curve
  double noise_sd = 0;                // of the weighted residuals
};
CalibrationEstimate estimate_calibration(const CalibrationStudy& study, const StudyRunOptions& control,
                                         const std::string& results_path);

}  // namespace rover::study
