// `rover calibrate`: fit any parameters of the rover and scenario files to
// measured drop curves by Levenberg-Marquardt, with Gauss-Newton intervals and
// the integration check, sample their posterior (--method mcmc), or rank the
// next experiment (--next-experiment). The formats: docs/configuration.md and
// docs/results_format.md; the method: study/studies/calibration.hpp.
#include <iostream>
#include <sstream>

#include "drivers/command_registry.hpp"
#include "drivers/study_options.hpp"
#include "io/input_files.hpp"
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
  io::InputFiles inputs;  // --data and --next-experiment (and what it names); the study's are checked above
  inputs.add(v.data_path, "--data");
  inputs.add_config(o.next_experiment, "--next-experiment");
  checks.not_an_input("--out", study_results_path(o.control, o.study_path), inputs, /*beside=*/true);
  checks.throw_if_any();
  std::stringstream ss(o.fit);
  for (std::string name; std::getline(ss, name, ',');)
    if (!name.empty()) o.overrides.fit.push_back(name);
  const study::CalibrationStudy s = study::load_calibration_study(o.study_path, o.overrides);
  o.control.resume_command = "the same command with --resume";
  if (mpi.rank() == 0) {
    if (!s.common.accuracy_choice.empty())
      std::cerr << "calibrate: \"accuracy\" chose " << s.common.accuracy_choice << "\n";
    if (s.method == study::CalibrationMethod::mcmc) {
      std::cerr << "calibrate: sampling the posterior of";
      for (const auto& p : s.fit) std::cerr << " " << p.name << " ~ " << p.prior.describe();
      std::cerr << (s.mcmc.sample_noise ? " and the noise sd" : "") << " given " << s.data_path << " ("
                << s.datasets.size() << " curve(s)): "
                << (s.mcmc.sampler == study::McmcSampler::independence ? "independence sampler, " : "ensemble sampler, ")
                << s.mcmc.walkers << " chains, at most " << s.mcmc.steps
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
    58, "calibrate", "Fit any parameters (c_q, f, k_q, ...) to measured drop curves, with intervals or a posterior",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<CalibrateOptions>();
      app.footer(std::string(
          "Fits the parameters of the study's \"fit\" (any number of the rover and scenario files by\n"
          "dotted name, the aliases c_q, f, M0_11 ... M0_42, M0_scale, and time_offset) to measured\n"
          "heights: B_l z for --data, or per curve of the study's \"data\" list B_l_z, B_r_z or G_z.\n"
          "DATA.csv has the header t,z (seconds, metres); its time origin need not be the release:\n"
          "each curve's offset is fitted with the rest. Levenberg-Marquardt stops on stated criteria\n"
          "and says whether it converged; then the best curves are re-run on Dormand-Prince, and the\n"
          "stiff integrator is tightened until its error moves no parameter by 0.1 standard error.\n"
          "Exit status 2: do not trust the intervals (not converged, no intervals, or the check\n"
          "failed); they are written flagged (/best intervals_valid = 0).\n"
          "--method mcmc samples the posterior from the converged fit until every effective sample\n"
          "size reaches mcmc.target_ess and nested R-hat < mcmc.max_rhat (exit 2 if not).\n"
          "--next-experiment ranks candidate drops by the intervals they are expected to give.\n"
          "Formats: docs/configuration.md, docs/results_format.md; a worked example: docs/studies.md.\n\n"
          "Examples:\n"
          "  rover calibrate --data configs/data/drop_horizontal_synthetic.csv --fit c_q\n"
          "  mpirun -np 2 rover calibrate --fit c_q,f,s_structure.k_q\n"
          "  rover calibrate --fit c_q,M0_scale --algorithm GN_DIRECT_L --max-evaluations 60\n"
          "  rover calibrate --study configs/studies/calibration_mcmc.json\n"
          "  rover calibrate --fit c_q,f --next-experiment configs/experiments/next_drop_candidates.json\n\n") +
          kMpiFooter);
      app.add_option("--study", o->study_path, "Study file (type calibration)")
          ->capture_default_str()->check(CLI::ExistingFile);
      app.add_option("--data", o->overrides.data_path, "Measured curve, CSV t,z (default: the study's)")
          ->check(CLI::ExistingFile);
      app.add_option("--fit", o->fit,
                     "Parameters to fit, comma-separated, by name: c_q, f, M0_scale, contact.k_g, "
                     "s_structure.k_q, ..., time_offset (bounds from the study's \"bounds\")");
      app.add_option("--algorithm", o->overrides.algorithm,
                     "levenberg_marquardt (default), or a derivative-free NLopt algorithm for a first search "
                     "that the least-squares iterations polish: LN_BOBYQA, GN_DIRECT_L, GN_CRS2_LM, ...");
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
