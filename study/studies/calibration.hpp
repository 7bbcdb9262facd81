// Calibration against measured drop curves, with uncertainty a user can
// trust (docs/model.md §8 for the channels).
//
// Fit (method "optimize", study/studies/calibration_fit.hpp): Levenberg-
// Marquardt on the residual vector of every curve, the curves' time offsets
// among its parameters, the Jacobian a central finite difference fanned out
// over MPI ranks; optionally after a first search by an NLopt algorithm
// ("algorithm"). It stops on stated criteria and says whether it converged.
// At the optimum the Gauss-Newton covariance (Bates & Watts 1988, section
// 2.3; study/estimators/least_squares_uncertainty.hpp) gives standard errors,
// 95 % intervals and correlations of the parameters and the offsets. Then the
// integration check (IntegrationCheck): the best curves are run again on the
// reference integrator, and while the shift that causes exceeds 0.1 standard
// error the integrator's tolerances are tightened and the fit repeated. A fit
// that did not converge, has no intervals, or fails the check is written
// flagged (/best intervals_valid = 0, not_valid_because) and the program
// exits with status 2.
//
// Posterior (method "mcmc", study/studies/calibration_mcmc.hpp): priors per
// parameter, a Gaussian likelihood; an independence sampler whose proposal is
// built on the converged fit (default), or the affine-invariant ensemble.
//
// Parameters: any number of the rover and scenario files by dotted name or
// alias (study/model/parameter_space.hpp: "c_q", "f", "contact.k_g",
// "M0_11", "M0_scale", "scenario.initial_q.z", ...) and "time_offset" (the
// data clock's time of the release; fitted for one curve, else each curve's
// offset is a parameter of its own, started at its profiled best). Positive
// scale parameters are searched in log10 (default for f and stiffnesses;
// "log_scale": {"name": true|false} to choose). The study file format is in
// docs/configuration.md.
//
// HDF5 result of a fit: /history (E x (p + K + 3) for K curves: the p
// parameters, K time offsets, pooled rms, objective, status; one row per
// evaluation in order; /history_columns names them), /history_start (E; -1
// for the least-squares iterations), /best/values (p), /best/names,
// /best/time_offset (K), /best/rms, /best/{names_uncertainty, covariance,
// correlation, stderr, lower, upper} (over the fitted parameters followed by
// the K offsets when they are not fitted), /best/noise_sd (K),
// /best/integration_shift (p, in standard errors), /data/t, /data/z, /fit/t,
// /fit/z (curve 0; curve k > 0 under /data/k, /fit/k), /data/curves;
// attributes of /best: converged, stop_reason, stop_message, intervals_valid,
// not_valid_because, iterations, integrator, gn_warning.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <memory>

#include "core/scenario.hpp"
#include "study/estimators/distributions.hpp"
#include "study/estimators/mcmc_diagnostics.hpp"
#include "study/model/study_model.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/model/qoi.hpp"
#include "study/studies/study_spec.hpp"

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
  std::string name;       // as the study names it: "c_q", "contact.k_g", "M0_scale", "time_offset"
  std::string canonical;  // its parameter-space name (study/model/parameter_space.hpp); empty for time_offset
  double lower = 0.0, upper = 0.0, initial = 0.0;
  bool log_scale = false;
  bool initial_given = false;  // "initial" names it; else the default start (the nominal value, 0 for time_offset)
  Distribution prior;  // mcmc: its prior (default uniform on [lower, upper])
};

// The prior as the posterior uses it: its description, and the bounds it is
// truncated to where its support reaches beyond them ("normal(mean 0.25,
// sd 5), truncated to the bounds [0.02, 1]").
std::string prior_within_bounds(const FitParameter& p);

// The coordinates a fit searches in: log10 for a log-scale parameter.
inline double fit_internal(const FitParameter& p, double value) { return p.log_scale ? std::log10(value) : value; }
inline double fit_natural(const FitParameter& p, double x) { return p.log_scale ? std::pow(10.0, x) : x; }

enum class CalibrationMethod { optimize, mcmc };

// The "algorithm" of a fit by Levenberg-Marquardt alone.
inline constexpr const char* kLeastSquaresAlgorithm = "levenberg_marquardt";

// The reference integrator of the integration check: Dormand-Prince at the
// tightest tolerances that run through every contact event of the drops.
IntegratorSettings reference_integrator();

// The samplers of the posterior (study/studies/calibration_mcmc.hpp).
enum class McmcSampler { independence, ensemble };
// Burn-in steps left out when the study names none: the independence
// sampler's chains start from the proposal, the ensemble's in a small ball.
inline constexpr long kIndependenceDiscard = 10;
inline constexpr long kEnsembleDiscard = 100;

// The largest settings a study file or the command line may give: fit starts,
// evaluations (and iterations) of one search, walkers, steps and burn-in of
// the posterior, its re-simulated draws, and points of one profile.
inline constexpr int kMaxCalibrationStarts = 100000;
inline constexpr int kMaxCalibrationEvaluations = 100000000;
inline constexpr int kMaxMcmcWalkers = 100000;
inline constexpr int kMaxMcmcSteps = 100000000;
inline constexpr int kMaxPredictiveDraws = 100000;
inline constexpr int kMinProfilePoints = 3, kMaxProfilePoints = 10000;

struct McmcSettings {
  McmcSampler sampler = McmcSampler::independence;
  int walkers = 32;  // the ensemble's walkers, or the independent chains
  // The chain runs until every parameter has an effective sample size of at
  // least target_ess and a nested R-hat (study/estimators/mcmc_diagnostics.hpp) below max_rhat (checked every
  // kMcmcCheckInterval steps past the burn-in), at most `steps` steps.
  // target_ess 0: exactly `steps` steps, no convergence requirement.
  long steps = 5000;
  std::optional<long> discard;  // burn-in steps left out of the summaries; default by sampler
  double target_ess = 400;
  double max_rhat = kDefaultMaxNestedRhat;
  std::uint64_t seed = 1;
  // The measurement noise sd [m]: sampled with noise_prior, or known.
  bool sample_noise = true;
  Distribution noise_prior = log_uniform(1e-6, 1e-2);
  double known_noise_sd_m = std::numeric_limits<double>::quiet_NaN();
  int predictive_draws = 40;  // posterior draws re-simulated for the predictive band
};

// The burn-in steps of a posterior run with `sampler`: the study's, else the
// sampler's default, at most half the steps (an independence study whose fit
// has no intervals runs the ensemble, and must still keep samples).
inline long mcmc_discard(const McmcSettings& m, McmcSampler sampler) {
  const long by_default = sampler == McmcSampler::independence ? kIndependenceDiscard : kEnsembleDiscard;
  return m.discard.value_or(std::min(by_default, m.steps / 2));
}

// One measured curve of a (joint) calibration: its scenario, the channel it
// measures (a name of calibration_channels()), its own time offset and noise
// level.
struct CalibrationDataset {
  std::string path, scenario_path, channel = "B_l_z";
  io::ScenarioSources sources;  // its scenario's documents
  // Simulates its scenario at the fitted parameters (all but time_offset, in
  // the order of CalibrationStudy::fit) with the study's integrator.
  std::shared_ptr<const RoverStudyModel> model;
  std::vector<double> t, z;
};

// The check that the fast integrator's error is below what the data resolve:
// the best curves are run again with `reference`, and the Gauss-Newton step
// that the difference causes is measured in standard errors of each fitted
// parameter. Above max_shift_se the integrator's tolerances are tightened
// tenfold and the fit repeated, at most max_tightenings times; then the
// reference integrator itself is used.
struct IntegrationCheck {
  double max_shift_se = 0.1;
  int max_tightenings = 3;
  IntegratorSettings reference;  // Dormand-Prince at rtol 1e-8, atol 1e-11
};

struct CalibrationStudy {
  StudyIdentity identity;       // path, type, name, description of the study file
  std::string accuracy_choice;  // the setting "accuracy" chose, in words (empty without "accuracy")
  // The integrator of every simulation of the calibration: the study's
  // "integrator", else the stiff one at its default tolerances.
  IntegratorSettings integrator;
  // Where `integrator` came from when the study chose none and the scenario's
  // differs ("the calibration's default, not the scenario's dopri5 at ...");
  // empty otherwise.
  std::string integrator_origin;
  IntegrationCheck integration_check;
  // Levenberg-Marquardt iterations (Jacobians) at most; 0: 10 + 5 p.
  int max_iterations = 0;
  std::string data_path;  // the data files, comma-separated (for messages)
  std::vector<CalibrationDataset> datasets;  // at least one
  std::vector<FitParameter> fit;
  CalibrationMethod method = CalibrationMethod::optimize;
  // "levenberg_marquardt" alone, or an NLopt algorithm for a first search
  // (max_evaluations simulations per start) that the least-squares
  // iterations then polish.
  std::string algorithm = "levenberg_marquardt";
  int max_evaluations = 40;
  double xtol_rel = 1e-3;
  // The keys of the study file that set the NLopt searches' budget
  // ("max_evaluations", "xtol_rel"): the first search and the profiles use
  // them, a least-squares fit alone does not.
  std::vector<std::string> search_budget_keys{};
  double offset_min_s = -0.2, offset_max_s = 0.2, offset_initial_s = 0.0;
  int starts = 1;
  std::uint64_t seed = 1;
  bool profile = false;     // profile-likelihood intervals after the fit
  int profile_points = 13;  // grid points per profiled parameter (>= 3)
  McmcSettings mcmc;
  // Covers the study file, every curve's data, scenario, rover and terrain
  // files, and every option that changes a result (command-line overrides
  // included).
  std::string fingerprint;

  bool offset_fitted() const;
  // Indices into `fit` of the parameters a simulation needs (all but time_offset).
  std::vector<std::size_t> simulated() const;
  // The initial values of `fit`, in its order.
  std::vector<double> initial_values() const;
  // Fitted values (order of `fit`) -> the simulated ones (order of simulated()).
  std::vector<double> simulated_values(const std::vector<double>& values) const;
  // The same study with every simulation on `integrator`.
  CalibrationStudy with_integrator(const IntegratorSettings& integrator) const;
};

// Command-line overrides; std::nullopt / empty: the study's.
struct CalibrationOverrides {
  std::string data_path{};
  std::vector<std::string> fit{};
  std::string algorithm{};
  std::string method{};
  std::optional<int> starts{}, max_evaluations{}, max_iterations{}, walkers{};
  std::optional<long> steps{}, discard{};
  bool profile = false;
};

// Throws io::ConfigError naming the file and the field on any bad value
// (an override's error names its flag instead).
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
// (bench/calibration_coverage.py); 1e-2 keeps them stable.
inline constexpr double kJacobianRelativeStep = 1e-2;

// "rosenbrock at rtol 1e-08, atol 2e-07" (", slip_tol 0.01" at another than the
// method's default), as results and messages name an integrator.
std::string describe_integrator(const IntegratorSettings& integrator);

}  // namespace rover::study
