// The check that a converged calibration fit is the lowest point around it
// and that its Gauss-Newton intervals describe the objective.
//
// A drop's objective is not smooth in every parameter: the friction
// sharpness f, for one, moves the instants of stick and slip, and the sum of
// squares gets ripples of about a standard error's width on top of its
// quadratic trend. Levenberg-Marquardt stops in whichever ripple it reaches,
// and the local curvature there can be ten times the trend's. So after the fit
// the objective is evaluated along each parameter's profile direction (the
// direction in which the linearised model re-fits the others as that one
// moves: column k of the covariance), at t = +-1, 2, 4, 8 standard errors:
//
//   delta_chi2(t) = (S(theta + t d_k) - S(theta)) / s^2,  d_k = C e_k / sqrt(C_kk),
//
// S the weighted sum of squares with the offsets at their profiled best, s the
// noise sd of the weighted residuals. The linear model predicts t^2.
//  * A point more than kLowerMargin below the fit is a better optimum: the fit
//    is repeated from the lowest such point.
//  * At the ends of the 95 % interval (t = 2) a delta_chi2 below
//    kFlatDeltaChi2 on either side means the objective is so much flatter
//    than its linearisation that the true interval is more than sqrt(2)
//    times as wide there: the intervals are flagged as not valid.
// Collective: the 8 p + 1 evaluations go through the task farm.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "study/studies/calibration.hpp"

namespace rover::study {

// The probe's multiples of the standard error, on each side.
inline constexpr double kProbeMultiples[] = {1.0, 2.0, 4.0, 8.0};
inline constexpr std::size_t kProbesPerSide = std::size(kProbeMultiples);
// A probe this many chi-square units below the fit is a better optimum.
inline constexpr double kLowerMargin = 0.25;
// At t = 2 the linear model predicts delta_chi2 = 4; below this the interval
// is more than sqrt(2) times too narrow on that side.
inline constexpr double kFlatDeltaChi2 = 2.0;

struct ProbeInput {
  std::vector<double> values;         // the fit, natural units, order of study.fit
  Eigen::MatrixXd covariance;         // of the fitted parameters (p x p, natural units)
  std::vector<double> curve_weights;  // per curve, as the fit weighted them
  double noise_sd = 0.0;              // of the weighted residuals
};

struct ProfileProbe {
  bool ok = false;
  std::string message;  // why not ok
  // Per fitted parameter, delta_chi2 at -8, -4, -2, -1, +1, +2, +4, +8 standard
  // errors along its profile direction (NaN where outside the bounds or a run
  // failed).
  Eigen::MatrixXd delta_chi2;
  // The lowest probe when it is more than kLowerMargin below the fit: its
  // values (natural units); empty otherwise.
  std::vector<double> better_values;
  double better_delta_chi2 = 0.0;
  // The parameters whose objective is flatter than the interval assumes.
  std::vector<std::string> flat;
};

// The signed multiples in the order of ProfileProbe::delta_chi2's columns.
std::vector<double> probe_multiples();

ProfileProbe probe_profile_directions(const CalibrationStudy& study, const ProbeInput& input,
                                      int progress_interval_s);

// One line per flagged parameter, for the console and /best not_valid_because.
std::string describe_flat_parameters(const ProfileProbe& probe, const CalibrationStudy& study);

}  // namespace rover::study
