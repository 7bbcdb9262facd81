// See calibration_program.hpp.
#include "study/studies/calibration_program.hpp"

#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "study/runtime/mpi_session.hpp"
#include "study/runtime/rank0_broadcast.hpp"
#include "study/studies/calibration_fit_flaw.hpp"
#include "study/studies/report_number.hpp"
#include "study/studies/study_output.hpp"

namespace rover::study {
namespace {

// Where the posterior starts: the converged fit and its covariance, on every
// rank; nothing when the fit has no finite intervals.
McmcStart posterior_start(const CheckedFit& checked) {
  if (!fit_has_intervals(checked)) return {};
  ProbeInput fit = probe_input_on_every_rank(checked);
  if (!fit.covariance.allFinite()) return {};
  return {std::move(fit.values), std::move(fit.covariance)};
}

// The banner of a fit: what is fitted to what, how, on how many ranks.
std::string fit_banner(const CalibrationStudy& s) {
  std::ostringstream text;
  text << "fitting";
  for (const FitParameter& p : s.fit) text << " " << p.name << " in [" << p.lower << ", " << p.upper << "]";
  text << " to " << s.data_path << " (" << s.datasets.size() << " curve(s)) with ";
  if (s.algorithm == kLeastSquaresAlgorithm)
    text << s.algorithm << " from \"initial\"";
  else
    text << s.algorithm << " (" << s.starts << " start(s) of at most " << s.max_evaluations
         << " simulations), then levenberg_marquardt";
  text << " on " << world_size() << " rank(s)";
  return text.str();
}

// The banner of a posterior run: the priors, the sampler and its target.
std::string posterior_banner(const CalibrationStudy& s) {
  std::ostringstream text;
  text << "sampling the posterior of";
  for (const FitParameter& p : s.fit) text << " " << p.name << " ~ " << prior_within_bounds(p);
  text << (s.mcmc.sample_noise ? " and the noise sd" : "") << " given " << s.data_path << " ("
       << s.datasets.size() << " curve(s)): "
       << (s.mcmc.sampler == McmcSampler::independence ? "independence sampler, " : "ensemble sampler, ")
       << s.mcmc.walkers << " chains, at most " << s.mcmc.steps << " steps";
  if (s.mcmc.target_ess > 0)
    text << ", until every effective sample size reaches " << format_number(s.mcmc.target_ess, 6)
         << " and R-hat < " << format_number(s.mcmc.max_rhat, 6);
  text << ", on " << world_size() << " rank(s)";
  return text.str();
}

// What every calibration program shares: the command, the name, the
// fingerprint, the banner (with the integrator "accuracy" chose) and the
// provenance attributes.
template <class Result>
StudyProgram<Result> calibration_program(const CalibrationStudy& s, const std::string& banner) {
  StudyProgram<Result> p;
  p.command = "calibrate";
  p.name = s.identity.name;
  p.fingerprint = s.fingerprint;
  p.banner = banner + "; every run on " + describe_integrator(s.integrator) +
             (s.integrator_origin.empty() ? "" : " (" + s.integrator_origin + ")");
  if (!s.accuracy_choice.empty()) p.banner += "; \"accuracy\" chose " + s.accuracy_choice;
  p.provenance = [s](io::Hdf5Writer& h5) { write_calibration_provenance(h5, s); };
  return p;
}

// The fit's evaluations as run counts: a failed simulation is a failed run.
RunCounts history_run_counts(const CalibrationStudy& study, const FitHistory& history) {
  RunCounts counts;
  const HistoryLayout row(study);
  for (std::size_t at = 0; at + row.width() <= history.rows.size(); at += row.width()) {
    ++counts.runs;
    if (history.rows[at + row.status()] == 0.0) continue;
    const std::size_t k = at / row.width();
    if (counts.failed++ == 0 && k < history.messages.size()) counts.first_failure = history.messages[k];
  }
  return counts;
}
RunCounts fit_run_counts(const CalibrationFitResult& r) { return history_run_counts(r.checked.study, r.history); }

}  // namespace

CalibrationPosteriorResult run_calibration_posterior(const CalibrationStudy& s, const StudyRunOptions& control) {
  FitHistory history;
  const CheckedFit checked = checked_fit(s, s.initial_values(), control, history);
  // Every run of the fit failed: the chains would fail alike, with no word of why.
  const RunCounts counts = world_rank() == 0 ? history_run_counts(checked.study, history) : RunCounts{};
  std::vector<double> all_failed{counts.runs > 0 && counts.failed == counts.runs ? 1.0 : 0.0};
  broadcast_from_rank0(all_failed);
  CalibrationPosteriorResult r{checked.study, true, "", {}, "", counts};
  if (all_failed[0] != 0.0) {
    if (world_rank() != 0) return r;
    // One run at the start says why the runs fail.
    const CalibrationCurve start = simulate_calibration_curve(checked.study, 0, checked.study.initial_values());
    r.not_sampled_because = "every one of the fit's " + std::to_string(counts.runs) + " runs failed (" +
                            (start.ok ? counts.first_failure : "at the initial values: " + start.message) +
                            "): the chains have no point to start from";
    r.fit_counts.first_failure = start.ok ? counts.first_failure : start.message;
    return r;
  }
  const McmcStart start = posterior_start(checked);
  // Every rank holds the same start, and so comes to the same verdict.
  r.not_sampled_because = mcmc_start_outside_priors(checked.study, start);
  if (!r.not_sampled_because.empty()) {
    r.fit_counts = {};  // the fit ran: its failed runs, if any, are no failure of the chains
    return r;
  }
  r.started_at_initial_values = start.values.empty();
  if (world_rank() == 0) r.start_fit_flaw = checked_fit_flaw(checked);
  r.posterior = run_calibration_mcmc(checked.study, control, start);
  return r;
}

void report_calibration_posterior_run(const CalibrationPosteriorResult& r, std::ostream& out) {
  if (!r.not_sampled_because.empty()) {
    out << "calibrate: no posterior: " << r.not_sampled_because << "\n";
    return;
  }
  out << "calibrate: the posterior started "
      << (r.started_at_initial_values ? "at the initial values (the fit has no intervals)" : "at the converged fit")
      << ", on " << describe_integrator(r.study.integrator) << "\n";
  if (!r.start_fit_flaw.empty())
    out << "calibrate: note: the least-squares fit the chains started from would be NOT VALID on its own: "
        << r.start_fit_flaw << "; the posterior's own checks below judge the chains\n";
  report_calibration_posterior(r.posterior, r.study, out);
}

void write_calibration_provenance(io::Hdf5Writer& h5, const CalibrationStudy& s) {
  write_base_provenance(h5, s.identity.type, s.identity.name, s.identity.path, &s.integrator, s.fingerprint);
}

namespace {

// The figures of a fit: the data and fit of each curve (<stem>.png,
// <stem>_1.png, ...) and the profile of each fitted parameter.
std::vector<PlannedFigure> fit_figures(const CalibrationStudy& s) {
  std::vector<PlannedFigure> figures;
  for (std::size_t k = 0; k < s.datasets.size(); ++k) {
    std::string suffix = k == 0 ? std::string(".png") : std::string("_") + std::to_string(k) + ".png";
    figures.push_back({std::move(suffix), "curve " + std::to_string(k)});
  }
  for (const FitParameter& f : s.fit) figures.push_back({"_profile_" + f.name + ".png", "the profile of " + f.name});
  return figures;
}

// The figures of a posterior named by the fitted parameters and the curves:
// traces, the corner plot, the predictive bands.
std::vector<PlannedFigure> posterior_figures(const CalibrationStudy& s) {
  std::vector<PlannedFigure> figures;
  for (const FitParameter& f : s.fit) figures.push_back({"_trace_" + f.name + ".png", "the trace of " + f.name});
  figures.push_back({"_corner.png", "the corner plot"});
  for (std::size_t c = 0; c < s.datasets.size(); ++c)
    figures.push_back({"_predictive" + (c == 0 ? std::string() : "_" + std::to_string(c)) + ".png",
                       "the predictive band of curve " + std::to_string(c)});
  return figures;
}

}  // namespace

StudyProgram<CalibrationFitResult> calibration_fit_program(CalibrationStudy study) {
  auto p = calibration_program<CalibrationFitResult>(study, fit_banner(study));
  p.run = [study](const StudyRuntime& runtime) {
    return run_calibration_fit(study, runtime.options, runtime.options.results_path);
  };
  p.write = [study](const CalibrationFitResult& r, io::Hdf5Writer& h5) { write_calibration_fit(r, study, h5); };
  p.counts = fit_run_counts;
  p.report = [study](const CalibrationFitResult& r, std::ostream& out) { report_calibration_fit(r, study, out); };
  p.plot = [study](const CalibrationFitResult& r, const std::string& path, PlotSelection) {
    plot_calibration_fit(r, study, path.substr(0, path.size() - 3));
  };
  p.figures = [study](PlotSelection) { return fit_figures(study); };
  p.verdict = [](const CalibrationFitResult& r) { return r.trusted ? 0 : kUntrustedStatus; };
  return p;
}

StudyProgram<CalibrationPosteriorResult> calibration_posterior_program(CalibrationStudy study) {
  auto p = calibration_program<CalibrationPosteriorResult>(study, posterior_banner(study));
  p.run = [study](const StudyRuntime& runtime) { return run_calibration_posterior(study, runtime.options); };
  p.write = [](const CalibrationPosteriorResult& r, io::Hdf5Writer& h5) {
    if (!r.not_sampled_because.empty()) {
      h5.attribute("/", "not_sampled_because", r.not_sampled_because);
      return;
    }
    write_calibration_posterior(r.posterior, r.study, h5);
    h5.attribute("/posterior", "start", std::string(r.started_at_initial_values ? "initial values" : "converged fit"));
    h5.attribute("/posterior", "start_fit_flaw", r.start_fit_flaw);
  };
  // The chains' proposals that fail are rejected moves, not failed runs; the
  // fit's runs count when every one failed and no chain started.
  p.counts = [](const CalibrationPosteriorResult& r) {
    return r.not_sampled_because.empty() ? RunCounts{} : r.fit_counts;
  };
  p.report = report_calibration_posterior_run;
  p.plot = [](const CalibrationPosteriorResult& r, const std::string& path, PlotSelection) {
    plot_calibration_posterior(r.posterior, r.study, path.substr(0, path.size() - 3));
  };
  p.figures = [study](PlotSelection) { return posterior_figures(study); };
  p.verdict = [](const CalibrationPosteriorResult& r) {
    return r.not_sampled_because.empty() && r.posterior.valid() ? 0 : kUntrustedStatus;
  };
  return p;
}

}  // namespace rover::study
