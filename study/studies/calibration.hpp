// Calibration against a measured drop curve, with uncertainty.
//
// Fit (method "optimize"): NLopt minimises the RMS between the simulated and
// the measured B_l z over chosen parameters within bounds; at the optimum the
// Gauss-Newton covariance of the least-squares estimate (Bates & Watts 1988,
// section 2.3; study/estimators/least_squares_uncertainty.hpp) gives standard errors, 95 %
// intervals and the correlation matrix of the fitted parameters AND the time
// offset. Its Jacobian is a central finite difference of the residual vector;
// the 2 p simulations are fanned out over MPI ranks.
//
// Posterior (method "mcmc", study/studies/calibration_mcmc.hpp): priors per parameter,
// a Gaussian likelihood, the affine-invariant ensemble sampler.
//
// Parameters that can be fitted: "c_q" [N m s/rad], "f" [1/rad] (searched in
// log10 by NLopt), "M0_scale" (multiplies all eight preloads), "time_offset"
// [s]. The measured curve's time origin need not be the release: data time t_d
// maps to simulation time t_d - time_offset. Unless time_offset is fitted it
// is profiled out: for every simulated curve the best offset in
// "time_offset_range" is found by a 1 ms scan and a golden-section polish
// (cheap: no new simulation). Before the release the simulated curve is held
// at its initial value, after the end at its final value.
//
// Study file (configs/studies/calibration.json):
//   {"type": "calibration", "name": "calibration", "scenario": "../scenarios/drop_horizontal.json",
//    "data": "../data/drop_horizontal_synthetic.csv",
//    "fit": ["c_q"], "algorithm": "LN_BOBYQA", "max_evaluations": 40, "xtol_rel": 1e-3,
//    "bounds": {"c_q": [0.02, 1.0], "f": [1e2, 1e5], "M0_scale": [0.8, 1.2], "time_offset": [-0.2, 0.2]},
//    "initial": {"c_q": 0.1, "f": 1e4, "M0_scale": 1.0, "time_offset": 0.0},
//    "starts": 1, "seed": 1,
//    "method": "optimize",                       (or "mcmc")
//    "priors": {"c_q": {"distribution": "uniform", "min": 0.02, "max": 1.0}},   (mcmc; default: uniform on the bounds)
//    "mcmc": {"walkers": 32, "steps": 500, "discard": 100, "seed": 1,
//             "noise_sd": {"distribution": "log_uniform", "min": 1e-6, "max": 1e-2},   (sampled; or a number: known)
//             "predictive_draws": 40}}
// "starts" > 1 runs that many local searches (start 0 from "initial", the
// others from seeded random points in the bounds), fanned out over MPI ranks.
// Gradient-based NLopt algorithms (LD_*, GD_*) are refused: the objective has
// no analytic gradient.
//
// Measured data: CSV with the header t,z (s, metres of the channel), read by
// io::read_measured_curve (the checks of `rover compare`: at least 3 rows,
// strictly increasing times, finite |z| < 1 km).
//
// Joint fits: "data" may be a list of curves,
//   [{"file": "../data/drop_horizontal_synthetic.csv"},
//    {"file": "../data/drop_skewed_synthetic.csv", "scenario": "../scenarios/drop_skewed.json",
//     "channel": "B_l_z"}]
// (scenario: default the study's; channel one of calibration_channels(): "B_l_z"
// (default), "B_r_z" or "G_z"), one
// parameter set for all, each curve with its own time offset (profiled; a
// fitted "time_offset" needs a single curve) and its own noise level. The fit
// then minimises sum_k n_k log RMS_k, the profile likelihood of independent
// Gaussian noise of unknown sd per curve (Bates & Watts 1988, section 2.2); the
// Gauss-Newton covariance weights each curve's residuals by 1 / s_k.
//
// HDF5 result of a fit: /history (E x (p + K + 3) for K curves: the p
// parameters, K time offsets, pooled rms, objective, status; one row per
// evaluation in order; /history_columns names them), /history_start (E),
// /best/values (p), /best/names, /best/time_offset (K), /best/rms, /best/
// {names_uncertainty, covariance, correlation, stderr, lower, upper} (over the
// fitted parameters followed by the K offsets when they are profiled),
// /best/noise_sd (K), /data/t, /data/z, /fit/t, /fit/z (curve 0, the best
// curve in data time; curve k > 0 under /data/k, /fit/k), /data/curves;
// attributes algorithm, nlopt_status (on / and /best), /best gn_warning.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "study/estimators/distributions.hpp"
#include "study/studies/montecarlo.hpp"
#include "study/model/qoi.hpp"
#include "study/studies/study_config.hpp"

namespace rover::study {

// A channel a measured curve may be: a height of study/model/qoi.hpp, in metres
// (docs/model.md §8). One list for `rover calibrate` and `rover synthesize`.
struct CalibrationChannel {
  std::string name;         // "B_l_z", as a study file's "channel" names it
  Channel channel = Channel::kBlz;
  std::string description;  // "world z of the left bogie pin B_l"
};
const std::vector<CalibrationChannel>& calibration_channels();  // B_l_z, B_r_z, G_z
// Throws std::invalid_argument "unknown channel 'x' (valid: B_l_z, B_r_z, G_z)".
const CalibrationChannel& calibration_channel(const std::string& name);

struct FitParameter {
  std::string name;
  double lower = 0.0, upper = 0.0, initial = 0.0;
  bool log_scale = false;
  Distribution prior;  // mcmc: its prior (default uniform on [lower, upper])
};

enum class CalibrationMethod { optimize, mcmc };

struct McmcSettings {
  int walkers = 32;
  long steps = 500;
  long discard = 100;  // burn-in steps left out of the summaries
  std::uint64_t seed = 1;
  // The measurement noise sd [m]: sampled with noise_prior, or known.
  bool sample_noise = true;
  Distribution noise_prior = log_uniform(1e-6, 1e-2);
  double known_noise_sd_m = std::numeric_limits<double>::quiet_NaN();
  int predictive_draws = 40;  // posterior draws re-simulated for the predictive band
};

// One measured curve of a (joint) calibration: its scenario, the channel it
// measures (a name of calibration_channels()), its own time offset and noise
// level.
struct CalibrationDataset {
  std::string path, scenario_path, channel = "B_l_z";
  io::ScenarioSetup setup;  // its scenario, with the study's integrator override
  std::vector<double> t, z;
};

struct CalibrationStudy {
  StudyCommon common;
  std::string data_path;  // the data files, comma-separated (for messages)
  std::vector<CalibrationDataset> datasets;  // at least one
  std::vector<FitParameter> fit;
  CalibrationMethod method = CalibrationMethod::optimize;
  std::string algorithm = "LN_BOBYQA";
  int max_evaluations = 40;
  double xtol_rel = 1e-3;
  double offset_min_s = -0.2, offset_max_s = 0.2, offset_initial_s = 0.0;
  int starts = 1;
  std::uint64_t seed = 1;
  bool profile = false;     // profile-likelihood intervals after the fit
  int profile_points = 13;  // grid points per profiled parameter (>= 3)
  McmcSettings mcmc;
  // Covers the study's files (common.fingerprint), the data file's text and
  // every option that changes a result (command-line overrides included).
  std::string fingerprint;

  bool offset_fitted() const;
};

// Command-line overrides; std::nullopt / empty: the study's.
struct CalibrationOverrides {
  std::string data_path{};
  std::vector<std::string> fit{};
  std::string algorithm{};
  std::string method{};
  std::optional<int> starts{}, max_evaluations{}, walkers{};
  std::optional<long> steps{}, discard{};
  bool profile = false;
};

// Throws io::ConfigError naming the file and the field on any bad value
// (overrides are reported under their study-file key).
CalibrationStudy load_calibration_study(const std::string& path, const CalibrationOverrides& overrides = {});

// Residuals z(t_d - offset) - z_d of a simulated curve (t, z) against the
// measured (t_d, z_d), z held constant outside the simulated interval.
std::vector<double> shifted_residuals(const std::vector<double>& t, const std::vector<double>& z,
                                      const std::vector<double>& t_d, const std::vector<double>& z_d,
                                      double offset);

// RMS of shifted_residuals.
double shifted_rms(const std::vector<double>& t, const std::vector<double>& z,
                   const std::vector<double>& t_d, const std::vector<double>& z_d, double offset);

// The offset in [lo, hi] minimising shifted_rms (scan + golden section).
double best_offset(const std::vector<double>& t, const std::vector<double>& z,
                   const std::vector<double>& t_d, const std::vector<double>& z_d, double lo,
                   double hi);

// The simulated channel of dataset `dataset` at fitted-parameter values
// (natural units, in the order of study.fit; a "time_offset" entry is ignored
// here). ok = false when the simulation failed (message says why).
struct CalibrationCurve {
  bool ok = false;
  std::string message;
  std::vector<double> t_s, z_m;
};
CalibrationCurve simulate_calibration_curve(const CalibrationStudy& study, std::size_t dataset,
                                            const std::vector<double>& values);

// The time offset that goes with a curve of a dataset: the fitted value if
// time_offset is among the parameters (one dataset only), otherwise the
// profiled best offset.
double offset_for(const CalibrationStudy& study, std::size_t dataset, const CalibrationCurve& curve,
                  const std::vector<double>& values);

// Every dataset at once: per dataset its offset and residual vector; ok =
// false if any simulation failed.
struct CalibrationResiduals {
  bool ok = false;
  std::string message;
  std::vector<double> offsets;
  std::vector<std::vector<double>> residuals;
};
CalibrationResiduals calibration_residuals(const CalibrationStudy& study, const std::vector<double>& values);

// Relative finite-difference step of the Gauss-Newton Jacobian. Far above
// cbrt(eps): the residuals come from an adaptive integrator whose error
// (~ its rtol, and not smooth in the parameters: the step sequence changes)
// would swamp a difference over a smaller step. With 1e-3 the stiff
// integrator's standard errors scattered by a factor 3 between noise seeds
// and the 95 % intervals held the truth 30 times in 40
// (bench/calibration_coverage.sh); 1e-2 keeps them stable.
inline constexpr double kJacobianRelativeStep = 1e-2;

// Collective over MPI ranks: the fit (method optimize) or the posterior
// (method mcmc). Rank 0 writes the HDF5 file and the PNGs; returns its path.
std::string run_calibration(const CalibrationStudy& study, const StudyRunControl& control);

}  // namespace rover::study
