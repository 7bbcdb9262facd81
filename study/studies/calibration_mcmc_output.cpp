// The result file and the console report of a calibration posterior
// (calibration_mcmc.hpp).
#include <cstdio>
#include <ostream>

#include "study/studies/calibration_mcmc.hpp"
#include "io/checkpoint.hpp"
#include "study/studies/report_number.hpp"

namespace rover::study {
namespace {

std::vector<double> as_vector(const Eigen::VectorXd& v) { return {v.begin(), v.end()}; }

// steps x (chains p), row-major: step, then chain, then parameter.
std::vector<double> flat_chain(const CalibrationPosterior& posterior) {
  std::vector<double> chain;
  for (long step = 0; step < posterior.steps; ++step)
    for (int c = 0; c < posterior.chains; ++c)
      for (const Eigen::MatrixXd& x : posterior.samples) chain.push_back(x(step, c));
  return chain;
}

std::string curve_group(const std::string& root, std::size_t curve) {
  return root + (curve == 0 ? std::string() : "/" + std::to_string(curve));
}

void write_diagnostics(const CalibrationPosterior& posterior, const McmcSettings& m, io::Hdf5Writer& h5) {
  const ChainDiagnostics& d = posterior.diagnostics;
  h5.write("/diagnostics/acceptance_fraction", std::vector<double>{d.acceptance_fraction});
  h5.write("/diagnostics/autocorrelation_time", as_vector(d.autocorrelation_time));
  h5.write("/diagnostics/effective_sample_size", as_vector(d.effective_sample_size));
  h5.write("/diagnostics/split_rhat", as_vector(d.split_rhat));
  h5.write("/diagnostics/nested_rhat", as_vector(d.nested_rhat));
  h5.attribute("/diagnostics", "warning", d.warning);
  h5.attribute("/diagnostics", "mixed", static_cast<long long>(posterior.mixed));
  h5.attribute("/diagnostics", "not_mixed_because", posterior.not_mixed_because);
  h5.write("/diagnostics/residual_lag1", posterior.residual_lag1);
  h5.write("/diagnostics/residual_rms", posterior.residual_rms_m);
  h5.attribute("/diagnostics", "lack_of_fit", posterior.lack_of_fit);
  h5.attribute("/diagnostics", "target_ess", m.target_ess);
  h5.attribute("/diagnostics", "max_rhat", m.max_rhat);
}

void write_predictive(const CalibrationPosterior& posterior, const CalibrationStudy& s, io::Hdf5Writer& h5) {
  for (std::size_t c = 0; c < posterior.predictive.size(); ++c) {
    const PredictiveBand& band = posterior.predictive[c];
    const std::string g = curve_group("/predictive", c);
    h5.write(g + "/t", band.t);
    h5.write(g + "/mean", band.mean);
    h5.write(g + "/lower", band.lower);
    h5.write(g + "/upper", band.upper);
    h5.write(g + "/lower_noise", band.lower_noise);
    h5.write(g + "/upper_noise", band.upper_noise);
    const std::string d = curve_group("/data", c);
    h5.write(d + "/t", s.datasets[c].t);
    h5.write(d + "/z", s.datasets[c].z);
  }
  h5.attribute("/predictive", "draws", static_cast<long long>(posterior.predictive_draws));
  h5.attribute("/predictive", "coverage", 0.9973);
}

}  // namespace

void write_calibration_posterior(const CalibrationPosterior& posterior, const CalibrationStudy& s, io::Hdf5Writer& h5) {
  const std::size_t p = posterior.names.size();
  h5.write("/chain", flat_chain(posterior), static_cast<std::size_t>(posterior.steps),
           static_cast<std::size_t>(posterior.chains) * p);
  h5.attribute("/chain", "shape", "steps x chains x parameters = " + std::to_string(posterior.steps) + " x " +
                                      std::to_string(posterior.chains) + " x " + std::to_string(p));
  h5.write("/log_posterior", posterior.log_posterior);
  h5.write("/posterior/names", posterior.names);
  h5.write("/posterior/mean", posterior.summary.mean);
  h5.write("/posterior/sd", posterior.summary.sd);
  h5.write("/posterior/q025", posterior.summary.q025);
  h5.write("/posterior/q975", posterior.summary.q975);
  h5.write("/posterior/map", posterior.summary.map);
  h5.attribute("/posterior", "discarded_steps", static_cast<long long>(posterior.discard));
  h5.attribute("/posterior", "sampler", posterior.sampler);
  h5.attribute("/posterior", "time_offset", s.offset_fitted() ? "sampled" : "profiled (best offset per proposal)");
  h5.attribute("/posterior", "noise_sd", s.mcmc.sample_noise ? "sampled: " + s.mcmc.noise_prior.describe()
                                                               : "known: " + format_number(s.mcmc.known_noise_sd_m, 6) + " m");
  for (const FitParameter& f : s.fit)
    h5.attribute("/posterior", "prior_" + f.name, prior_within_bounds(f));
  write_diagnostics(posterior, s.mcmc, h5);
  write_predictive(posterior, s, h5);
  h5.attribute("/", "data_file", s.data_path);
  h5.attribute("/", "method", std::string("mcmc"));
  h5.attribute("/", "integrator", describe_integrator(s.integrator));
  h5.attribute("/", "walkers", static_cast<long long>(posterior.chains));
  h5.attribute("/", "steps", static_cast<long long>(posterior.steps));
  h5.unsigned_attribute("/", "seed", s.mcmc.seed);
  h5.attribute("/", "calibration_fingerprint", io::key_summary(s.fingerprint));
}

void report_calibration_posterior(const CalibrationPosterior& posterior, const CalibrationStudy& s,
                                  std::ostream& out) {
  if (!posterior.mixed)
    out << "calibrate: WARNING: the posterior is NOT VALID: " << posterior.not_mixed_because
        << " (written with /diagnostics mixed = 0; exit status 2)\n";
  if (!posterior.lack_of_fit.empty())
    out << "calibrate: WARNING: the posterior is NOT VALID: " << posterior.lack_of_fit
        << " (written with /diagnostics lack_of_fit; exit status 2)\n";
  out << "calibrate: posterior from the " << posterior.sampler << " sampler, " << posterior.chains << " chains x "
      << posterior.steps << " steps (first " << posterior.discard << " discarded); time offset "
      << (s.offset_fitted() ? "sampled" : "profiled (best offset for each proposal)") << "\n";
  const ChainDiagnostics& d = posterior.diagnostics;
  const PosteriorSummary& m = posterior.summary;
  const double kept_draws = static_cast<double>(posterior.chains) * static_cast<double>(posterior.steps - posterior.discard);
  for (std::size_t k = 0; k < posterior.names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    const double ess = d.effective_sample_size[i];
    out << "  " << posterior.names[k] << " = " << format_number(m.mean[k], 6) << " +- " << format_number(m.sd[k], 3)
        << " (sd); 95 % [" << format_number(m.q025[k], 6) << ", " << format_number(m.q975[k], 6) << "]; MAP "
        << format_number(m.map[k], 6) << "; tau " << format_number(d.autocorrelation_time[i], 3) << ", ESS "
        << format_number(ess, 3)
        << (ess > kept_draws ? " (more than the " + format_number(kept_draws, 6) +
                                   " kept draws: a tau below 1 is an estimate from too short a chain)"
                             : std::string())
        << ", nested R-hat " << format_number(d.nested_rhat[i], 5) << "\n";
  }
  out << "calibrate: acceptance " << format_number(d.acceptance_fraction, 3) << "; at the MAP, residual RMS";
  for (double rms : posterior.residual_rms_m) out << " " << format_residual_statistic(rms, 4, "m");
  out << ", residual lag-1 autocorrelation";
  for (double lag1 : posterior.residual_lag1) out << " " << format_residual_statistic(lag1, 2);
  out << " (independent noise: near 0)\n";
  // With a target met the warning's rule of thumb (50 autocorrelation times) is moot.
  if (!d.warning.empty() && (!posterior.mixed || s.mcmc.target_ess <= 0)) out << "calibrate: WARNING: " << d.warning << "\n";
}

}  // namespace rover::study
