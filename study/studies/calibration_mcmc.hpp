// Bayesian calibration: the posterior of the fitted parameters (and of the
// measurement noise sd) given measured drop curves.
//
// Model: z_d,i = z_sim(t_d,i - offset; theta) + e_i, e_i ~ N(0, sigma^2)
// independent, so log L = -n/2 log(2 pi sigma^2) - RSS / (2 sigma^2). sigma is
// known ("mcmc": {"noise_sd": 1e-4}) or sampled with its own prior (default
// log-uniform, the scale-invariant choice). The time offset is sampled when it
// is among the fitted parameters; otherwise it is PROFILED: each proposal uses
// its best offset (a maximisation, not a marginalisation, over the offset).
// Every prior is truncated to the parameter's bounds: a point outside them
// has density 0 and is rejected without a simulation.
//
// Samplers ("mcmc": {"sampler": ...}), both in the fit's coordinates (log10
// for a log-scale parameter and for the noise sd, with the Jacobian of that
// map in the density):
//  * "independence" (default): independence Metropolis-Hastings
//    (study/estimators/independence_sampler.hpp) from a Student-t on the
//    converged fit and its Gauss-Newton covariance. Close to the posterior,
//    so its steps are nearly independent: tens of steps reach the target.
//  * "ensemble": the affine-invariant ensemble sampler
//    (study/estimators/ensemble_sampler.hpp), walkers started in a small ball
//    around the fit; needs no covariance, mixes more slowly.
// The chains run until every parameter's effective sample size and nested
// R-hat meet the study's target (McmcSettings), printing their progress; a
// chain that ends at its step limit without meeting them is written with
// /diagnostics mixed = 0 and the program exits with status 2. So is a
// posterior whose MAP leaves correlated residuals, or residuals far above a
// given noise sd (calibration_lack_of_fit.hpp): /diagnostics lack_of_fit.
//
// Parallel: all ranks step the sampler in lockstep (its proposals depend only
// on the state and the seed); the proposals of a step are evaluated in ONE
// task farm and rank 0 broadcasts their log densities, so the chain is
// identical for any number of ranks. The state after every step is
// checkpointed beside the result file; --resume continues from the last one
// exactly as an uninterrupted run, and a signal ends the study after the step
// in progress, the checkpoint saved.
//
// HDF5 result (docs/results_format.md): /chain (steps x (chains p), natural
// units), /log_posterior, /posterior/{names, mean, sd, q025, q975, map},
// /diagnostics/{acceptance_fraction, autocorrelation_time,
// effective_sample_size, split_rhat, nested_rhat} with attributes mixed and
// not_mixed_because, /predictive[/c]/{t, mean, lower, upper, lower_noise,
// upper_noise} (the 99.73 % band over the data times from predictive_draws
// re-simulated draws, without and with noise), /data[/c]/{t, z}.
#pragma once

#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/hdf5_file.hpp"
#include "study/estimators/distributions.hpp"
#include "study/estimators/mcmc_diagnostics.hpp"
#include "study/studies/calibration.hpp"

namespace rover::study {

// Gaussian log likelihood of independent residuals with standard deviation
// noise_sd > 0: -n/2 log(2 pi sd^2) - sum r^2 / (2 sd^2).
double gaussian_log_likelihood(const std::vector<double>& residuals, double noise_sd);

// Per curve, the residual vector at parameter values; std::nullopt when the
// model failed.
using ResidualFunction =
    std::function<std::optional<std::vector<std::vector<double>>>(const std::vector<double>& parameters)>;

// The log posterior density (up to a constant) of theta = (the parameters,
// with `priors`, then, unless known_noise_sd is given, one noise sd per curve
// with noise_prior): sum of log priors + sum over the `curves` curves of
// gaussian_log_likelihood(residuals_k, sd_k). -inf outside the priors'
// support (the model is then not run) or when the model failed.
double calibration_log_density(const std::vector<Distribution>& priors, const Distribution& noise_prior,
                               std::optional<double> known_noise_sd, std::size_t curves,
                               const Eigen::VectorXd& theta, const ResidualFunction& residuals);

// The posterior's summaries over the kept steps, per sampled parameter.
struct PosteriorSummary {
  std::vector<double> mean, sd, q025, q975, map;
};

// The posterior predictive band of one curve over its data times [m].
struct PredictiveBand {
  std::vector<double> t, mean, lower, upper, lower_noise, upper_noise;
};

struct CalibrationPosterior {
  std::vector<std::string> names;  // the fitted parameters, then noise_sd per curve when sampled
  std::string sampler;             // "independence" or "ensemble"
  std::vector<Eigen::MatrixXd> samples;  // per parameter: steps x chains, natural units (noise sd in m)
  Eigen::MatrixXd log_posterior;         // steps x chains
  long steps = 0, discard = 0;
  int chains = 0;
  ChainDiagnostics diagnostics;
  PosteriorSummary summary;
  std::vector<PredictiveBand> predictive;  // per curve; empty bands when no draw ran
  int predictive_draws = 0;                // draws that ran
  bool mixed = true;                       // the target was met (or none was set)
  std::string not_mixed_because;
  // At the MAP (calibration_lack_of_fit.hpp): per curve, the residuals' lag-1
  // autocorrelation and RMS, and why the model does not describe the data
  // (empty when it does).
  std::vector<double> residual_lag1, residual_rms_m;
  std::string lack_of_fit;

  // Mixed, and describing the data: a posterior to use.
  bool valid() const { return mixed && lack_of_fit.empty(); }
};

// Where a posterior starts: the converged fit (values in the order of
// CalibrationStudy::fit, their Gauss-Newton covariance in natural units), or
// nothing (the study's initial values; the ensemble sampler then).
struct McmcStart {
  std::vector<double> values;
  Eigen::MatrixXd covariance;
};

// Why the chains cannot start from `start` (empty when they can): the centre
// they start around (the least-squares estimate, or the initial values, and
// each curve's residual RMS as its noise sd) lies outside a prior's support
// truncated to the bounds: the data and the prior disagree. Names the prior
// (priors.<name> or mcmc.noise_sd), its support and the value. Runs one
// simulation per curve, on the calling rank only.
std::string mcmc_start_outside_priors(const CalibrationStudy& study, const McmcStart& start);

// Collective over MPI ranks. The result is complete on rank 0; the other
// ranks hold `mixed` only. Throws StudyInterrupted after a signal, the
// checkpoint saved.
CalibrationPosterior run_calibration_mcmc(const CalibrationStudy& study, const StudyRunOptions& control,
                                          const McmcStart& start);

// Rank 0: the result file's datasets and attributes (not the provenance).
void write_calibration_posterior(const CalibrationPosterior& posterior, const CalibrationStudy& study,
                                 io::Hdf5Writer& h5);
// The console summary: parameters, intervals, diagnostics and warnings.
void report_calibration_posterior(const CalibrationPosterior& posterior, const CalibrationStudy& study,
                                  std::ostream& out);
// The figures beside the result: traces, the corner plot and the
// predictive band of each curve (stem: the result path without ".h5").
void plot_calibration_posterior(const CalibrationPosterior& posterior, const CalibrationStudy& study,
                                const std::string& stem);

}  // namespace rover::study
