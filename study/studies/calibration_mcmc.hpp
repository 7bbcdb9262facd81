// Bayesian calibration: the posterior of the fitted parameters (and of the
// measurement noise sd) given a measured drop curve, sampled with the
// affine-invariant ensemble sampler (Goodman & Weare 2010; Foreman-Mackey et
// al. 2013; study/estimators/ensemble_sampler.hpp).
//
// Model: z_d,i = z_sim(t_d,i - offset; theta) + e_i, e_i ~ N(0, sigma^2)
// independent, so log L = -n/2 log(2 pi sigma^2) - RSS / (2 sigma^2). sigma is
// known ("mcmc": {"noise_sd": 1e-4}) or sampled with its own prior (default
// log-uniform, the scale-invariant choice). The time offset is sampled when it
// is among the fitted parameters; otherwise it is PROFILED: each proposal uses
// its best offset (a maximisation, not a marginalisation, over the offset).
//
// The chain runs until its effective sample size and split R-hat meet the
// study's target (McmcSettings), printing their progress; a chain that ends
// at its step limit without meeting them is written with
// /diagnostics mixed = 0 and the program exits with status 2.
//
// Parallel: all ranks run the sampler in lockstep (its proposals depend only on
// the state and the seed); the proposals of each half-ensemble are evaluated
// in ONE run_task_farm call and rank 0 broadcasts their log densities, so the
// chain is identical for any number of ranks. The state after every step is
// checkpointed beside the result file; --resume continues from the last one
// exactly as an uninterrupted run.
//
// HDF5 result: /chain (steps x (walkers p), row-major, i.e. steps x walkers x
// p; attribute shape; p = the fitted parameters, then noise_sd per curve when
// sampled), /log_posterior (steps x walkers), /posterior/{names,
// mean, sd, q025, q975, map} (after the discarded burn-in),
// /diagnostics/{acceptance_fraction, autocorrelation_time,
// effective_sample_size, split_rhat} and attribute warning,
// /predictive/{t, mean, lower, upper, lower_noise, upper_noise} (the 99.73 %
// band of B_l z over the data times, from predictive_draws posterior draws
// re-simulated; with noise: each draw plus Gaussian noise of its sd; 25
// noise replicates per draw). Joint fits: curve c > 0 at /predictive/c/...
// and /data/c/...
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "study/studies/calibration.hpp"
#include "study/estimators/distributions.hpp"

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

// Collective over MPI ranks; see above. The walkers start in a ball around
// `start` (a tenth of each standard error) when it is given. Returns the
// result path and whether the chain met its target (mixed).
CalibrationOutcome run_calibration_mcmc(const CalibrationStudy& study, const StudyRunControl& control,
                                        const McmcStart& start = {});

}  // namespace rover::study
