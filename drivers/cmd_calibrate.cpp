// `rover calibrate`: fit c_q (and f, M0_scale, time_offset) to a measured drop
// curve with any derivative-free NLopt algorithm, with Gauss-Newton intervals
// at the optimum, or sample their posterior (--method mcmc). See
// study/studies/calibration.hpp and study/studies/calibration_mcmc.hpp for the formats.
#include <iostream>
#include <sstream>

#include "drivers/command_registry.hpp"
#include "drivers/study_options.hpp"
#include "core/number_text.hpp"
#include "study/studies/calibration.hpp"
#include "study/studies/next_experiment.hpp"
#include "study/runtime/mpi_session.hpp"

namespace rover::cli {
namespace {

struct CalibrateOptions {
  std::string study_path = "configs/studies/calibration.json";
  std::string fit;
  std::string next_experiment;  // candidates file
  study::CalibrationOverrides overrides;
  study::StudyRunControl control;
};

int run_calibrate_command(CalibrateOptions o) {
  study::MpiSession mpi(nullptr, nullptr);
  FlagChecks checks;
  const study::CalibrationOverrides& v = o.overrides;
  if (v.starts && *v.starts < 1) checks.add("--starts must be at least 1, got " + std::to_string(*v.starts));
  if (v.max_iterations && *v.max_iterations < 1)
    checks.add("--max-iterations must be at least 1, got " + std::to_string(*v.max_iterations));
  if (v.max_evaluations && *v.max_evaluations < 1)
    checks.add("--max-evaluations must be at least 1, got " + std::to_string(*v.max_evaluations));
  if (v.walkers && (*v.walkers < 2 || *v.walkers % 2 != 0))
    checks.add("--walkers must be an even number of at least 2, got " + std::to_string(*v.walkers));
  if (v.steps && *v.steps < 1) checks.add("--steps must be at least 1, got " + std::to_string(*v.steps));
  if (v.discard && *v.discard < 0) checks.add("--discard must not be negative, got " + std::to_string(*v.discard));
  check_study_output(checks, o.control, o.study_path);
  checks.distinct_files("--out", o.control.results_path, "--data", v.data_path);
  checks.distinct_files("--out", o.control.results_path, "--next-experiment", o.next_experiment);
  checks.throw_if_any();
  std::stringstream ss(o.fit);
  for (std::string name; std::getline(ss, name, ',');)
    if (!name.empty()) o.overrides.fit.push_back(name);
  const study::CalibrationStudy s = study::load_calibration_study(o.study_path, o.overrides);
  o.control.resume_command = "the same command with --resume";
  if (mpi.rank() == 0) {
    if (s.method == study::CalibrationMethod::mcmc) {
      std::cerr << "calibrate: sampling the posterior of";
      for (const auto& p : s.fit) std::cerr << " " << p.name << " ~ " << p.prior.describe();
      std::cerr << (s.mcmc.sample_noise ? " and the noise sd" : "") << " given " << s.data_path << " ("
                << s.datasets.size() << " curve(s)): " << s.mcmc.walkers << " walkers, at most " << s.mcmc.steps
                << " steps" << (s.mcmc.target_ess > 0 ? ", until every effective sample size reaches " +
                                                             number_text(s.mcmc.target_ess) + " and R-hat < " +
                                                             number_text(s.mcmc.max_rhat) : std::string())
                << ", on " << mpi.size() << " rank(s)\n";
    } else {
      std::cerr << "calibrate: fitting";
      for (const auto& p : s.fit) std::cerr << " " << p.name << " in [" << p.lower << ", " << p.upper << "]";
      std::cerr << " to " << s.data_path << " (" << s.datasets.size() << " curve(s)) with " << s.algorithm
                << ", " << s.starts << " start(s) on " << mpi.size() << " rank(s)\n";
    }
  }
  return run_interruptible("calibrate", [&] {
    const study::CalibrationOutcome outcome = o.next_experiment.empty()
                                                  ? study::run_calibration(s, o.control)
                                                  : study::run_next_experiment(s, o.next_experiment, o.control);
    return outcome.trusted ? 0 : 2;
  });
}

const RegisterCommand registration{
    58, "calibrate", "Fit c_q (and f, M0_scale, time offset) to a measured drop curve, with intervals or a posterior",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<CalibrateOptions>();
      app.footer(std::string(
          "Minimises the RMS between simulated and measured B_l z (or, per curve of the study's\n"
          "\"data\" list, B_r_z or G_z). DATA.csv has the header t,z (seconds, metres of the\n"
          "channel, the left bogie pin for --data); its time origin need not be the release: the\n"
          "offset is profiled out (or fitted, with --fit ...,time_offset). Bounds, initial values\n"
          "and the scenario come from the study file. Writes /history (every evaluation),\n"
          "/best (with Gauss-Newton standard errors, 95 % intervals, covariance and correlation of\n"
          "the parameters and the time offset, and NLopt's return status), /data, /fit and a PNG.\n"
          "--method mcmc samples the posterior (priors from the study's \"priors\", noise sd\n"
          "known or sampled) with an ensemble sampler: /chain, /posterior, /diagnostics,\n"
          "/predictive (99.73 % band of each curve's channel), traces, the corner plot and the band as PNGs.\n\n"
          "Examples:\n"
          "  rover calibrate --data configs/data/drop_horizontal_synthetic.csv --fit c_q --algorithm LN_BOBYQA\n"
          "  rover calibrate --fit c_q,M0_scale --algorithm GN_DIRECT_L --max-evaluations 60\n"
          "  mpirun -np 4 rover calibrate --fit c_q,f --starts 4\n"
          "  rover calibrate --study configs/studies/calibration_mcmc.json --method mcmc\n\n") + kMpiFooter);
      app.add_option("--study", o->study_path, "Study file (type calibration)")
          ->capture_default_str()->check(CLI::ExistingFile);
      app.add_option("--data", o->overrides.data_path, "Measured curve, CSV t,z (default: the study's)")
          ->check(CLI::ExistingFile);
      app.add_option("--fit", o->fit, "Parameters to fit, comma-separated: c_q, f, M0_scale, time_offset");
      app.add_option("--algorithm", o->overrides.algorithm,
                     "Any derivative-free NLopt algorithm by name: LN_BOBYQA, LN_NELDERMEAD, LN_SBPLX, "
                     "GN_DIRECT_L, GN_CRS2_LM, GN_ISRES, G_MLSL_LDS (with a BOBYQA local search), ...");
      app.add_option("--starts", o->overrides.starts, "Number of independent starts (fanned out over ranks)");
      app.add_option("--max-evaluations", o->overrides.max_evaluations,
                     "Simulations per start of an NLopt first search (--algorithm)");
      app.add_option("--max-iterations", o->overrides.max_iterations,
                     "Least-squares iterations (Jacobians) at most; default 10 + 5 per fitted parameter");
      app.add_flag("--profile", o->overrides.profile,
                   "After the fit: profile-likelihood intervals of every fitted parameter (the others "
                   "re-optimised along a grid), a PNG each; says when a parameter is not identifiable");
      app.add_option("--method", o->overrides.method, "optimize (default) or mcmc")
          ->check(CLI::IsMember({"optimize", "mcmc"}));
      app.add_option("--walkers", o->overrides.walkers, "mcmc: ensemble walkers (even, >= 2 x sampled parameters)");
      app.add_option("--steps", o->overrides.steps, "mcmc: ensemble steps");
      app.add_option("--discard", o->overrides.discard, "mcmc: burn-in steps left out of the summaries");
      app.add_option("--next-experiment", o->next_experiment,
                     "Rank the candidate experiments of this JSON file by the 95 % interval each parameter is "
                     "expected to have once their curve is added (after fitting the study's data); writes the "
                     "table (default results/<name>_next_experiment.h5)")
          ->check(CLI::ExistingFile);
      add_study_control(app, o->control);
      return [o] { return run_calibrate_command(*o); };
    }};

}  // namespace
}  // namespace rover::cli
