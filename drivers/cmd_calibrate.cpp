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
#include "study/studies/calibration.hpp"
#include "study/studies/calibration_program.hpp"
#include "study/studies/next_experiment.hpp"

namespace rover::cli {
namespace {

constexpr int kMaxStarts = study::kMaxCalibrationStarts;
constexpr int kMaxEvaluations = study::kMaxCalibrationEvaluations;
constexpr int kMaxWalkers = study::kMaxMcmcWalkers;
constexpr long kMaxSteps = study::kMaxMcmcSteps;

struct CalibrateOptions {
  std::string study_path = "configs/studies/calibration.json";
  std::string fit;
  std::string next_experiment;  // candidates file
  study::CalibrationOverrides overrides;
  study::StudyRunOptions run;
};

// --data and --next-experiment (and the files it names) are inputs too: --out
// never replaces them. The study file's own are checked by run_study_command.
void check_flag_inputs(const CalibrateOptions& o) {
  FlagChecks checks;
  const study::CalibrationOverrides& v = o.overrides;
  io::InputFiles inputs;
  inputs.add(v.data_path, "--data");
  inputs.add_config(o.next_experiment, "--next-experiment");
  // A ranking (--next-experiment) draws no figure.
  const bool draws = o.run.plots != study::PlotSelection::kNone && o.next_experiment.empty();
  checks.not_an_input("--out", study_results_path(o.run, o.study_path), inputs,
                      draws ? io::WrittenBeside::kTemporariesAndPlots : io::WrittenBeside::kTemporaries);
  checks.throw_if_any();
}

// What the outputs must not replace: the study file, every curve's data,
// scenario and the files that names, and --next-experiment with its files.
io::InputFiles calibration_inputs(const CalibrateOptions& o, const study::CalibrationStudy& s) {
  io::InputFiles inputs;
  inputs.add(o.study_path, "--study");
  for (const study::CalibrationDataset& d : s.datasets) {
    inputs.add(d.path, "'data' in " + o.study_path);
    inputs.add(d.scenario_path, "'scenario' in " + o.study_path);
    inputs.add_all(d.sources.files);
  }
  if (!o.next_experiment.empty()) inputs.add_config(o.next_experiment, "--next-experiment");
  return inputs;
}

// The study flags a calibration would not use: a ranking draws no figure,
// and only a global first search and a posterior keep a checkpoint (a
// least-squares fit alone has nothing to resume).
void refuse_study_flags_without_use(const CLI::App& app, bool ranking, bool checkpointed, FlagChecks& checks) {
  if (ranking && app.count("--plots") > 0)
    checks.add("--plots: --next-experiment writes a ranking and draws no figure; drop --plots");
  if (checkpointed) return;
  for (const char* flag : {"--resume", "--checkpoint-every"})
    if (app.count(flag) > 0)
      checks.add(std::string(flag) + ": a least-squares fit (levenberg_marquardt) keeps no checkpoint, so there is "
                 "nothing to resume or flush; drop it (a global first search, --algorithm GN_..., or --method "
                 "mcmc keeps one)");
}

// The NLopt searches' settings: --starts serves the first search only,
// --max-evaluations that and the profiles; a least-squares fit alone uses
// neither. The same keys of the study file, which other flags may put to
// use, are noted instead.
void refuse_search_settings_without_use(const CalibrateOptions& o, const study::CalibrationStudy& s, bool profiles,
                                        FlagChecks& checks) {
  if (s.algorithm != study::kLeastSquaresAlgorithm) return;
  const study::CalibrationOverrides& v = o.overrides;
  if (v.starts)
    checks.add("--starts " + std::to_string(*v.starts) + ": independent starts need an NLopt first search (--algorithm "
               "LN_BOBYQA, GN_DIRECT_L, ...); the least-squares fit (levenberg_marquardt) starts once, at the "
               "study's \"initial\": drop --starts, or give --algorithm");
  if (profiles) return;
  if (v.max_evaluations)
    checks.add("--max-evaluations " + std::to_string(*v.max_evaluations) + " bounds the simulations of an NLopt first "
               "search (--algorithm) or of each profile point (--profile); the least-squares fit "
               "(levenberg_marquardt) is bounded by --max-iterations instead");
  else if (!s.search_budget_keys.empty())
    std::cerr << "rover calibrate: note: " << s.search_budget_keys.front()
              << (s.search_budget_keys.size() > 1 ? " and " + s.search_budget_keys.back() : "") << " in " << o.study_path
              << " bound an NLopt first search (\"algorithm\") or the profiles (\"profile\"), and this fit runs "
                 "neither: levenberg_marquardt alone is bounded by \"max_iterations\"\n";
}

// Flags the chosen program would not use are refused, never dropped:
// --next-experiment ranks after a least-squares fit (no posterior, no
// profiles), a posterior (mcmc) computes no profile, and the sampler's sizes apply to
// mcmc only.
void refuse_flags_that_do_not_apply(const CLI::App& app, const CalibrateOptions& o, const study::CalibrationStudy& s) {
  FlagChecks checks;
  const study::CalibrationOverrides& v = o.overrides;
  const bool ranking = !o.next_experiment.empty();
  const bool mcmc = s.method == study::CalibrationMethod::mcmc;
  const bool posterior = !ranking && mcmc;
  const std::string method = v.method.empty() ? std::string("the study's \"method\" (") +
                                                    (mcmc ? "mcmc" : "optimize") + ", " + o.study_path + ")"
                                              : "--method " + v.method;
  if (ranking && mcmc)
    checks.add("--next-experiment ranks the candidates after a least-squares fit and samples no posterior: it "
               "does not go with " + method + "; give --method optimize, or drop --next-experiment");
  refuse_study_flags_without_use(app, ranking, posterior || s.algorithm != study::kLeastSquaresAlgorithm, checks);
  if (ranking && v.profile)
    checks.add("--profile: --next-experiment ranks the candidates from the fit's Jacobian and computes no profile "
               "likelihoods: drop --profile, or run the calibration alone with --profile");
  else if (ranking && s.profile)
    std::cerr << "rover calibrate: note: the profile likelihoods that " << o.study_path
              << " asks for (\"profile\": true) are not computed: --next-experiment ranks from the fit's Jacobian\n";
  refuse_search_settings_without_use(o, s, s.profile && !ranking && !mcmc, checks);
  if (v.profile && posterior)
    checks.add("--profile: profile likelihoods follow a least-squares fit, and " + method +
               " samples the posterior instead, computing none: drop --profile or give --method optimize");
  if (!posterior) {
    const std::string why =
        ranking ? "--next-experiment ranks after a least-squares fit" : method + " fits by least squares";
    if (v.walkers) checks.add("--walkers " + std::to_string(*v.walkers) + " applies to --method mcmc only; " + why);
    if (v.steps) checks.add("--steps " + std::to_string(*v.steps) + " applies to --method mcmc only; " + why);
    if (v.discard) checks.add("--discard " + std::to_string(*v.discard) + " applies to --method mcmc only; " + why);
  }
  checks.throw_if_any();
}

study::CalibrationStudy load_study(const CalibrateOptions& o) {
  check_flag_inputs(o);
  study::CalibrationOverrides overrides = o.overrides;
  FlagChecks checks;
  overrides.fit = split_names("--fit", o.fit, checks);
  checks.throw_if_any();
  return study::load_calibration_study(o.study_path, overrides);
}

int run_calibrate_command(const CLI::App& app, CalibrateOptions o) {
  if (!o.next_experiment.empty() && o.run.results_path.empty()) {
    // The ranking's default file: results/<study name>_next_experiment.h5.
    const std::string fit_path = study_results_path(o.run, o.study_path);
    if (fit_path.ends_with(".h5")) {
      o.run.results_path = fit_path.substr(0, fit_path.size() - 3) + "_next_experiment.h5";
      o.run.results_path_is_default = true;
    }
  }
  return run_study_session(app, o.run, o.study_path, [&](const study::StudyRunOptions& options) {
    study::CalibrationStudy s = load_study(o);
    refuse_flags_that_do_not_apply(app, o, s);
    const io::InputFiles inputs = calibration_inputs(o, s);
    auto drive = [&](auto program) {
      program.inputs = inputs;
      return study::drive_study(program, options);
    };
    if (!o.next_experiment.empty()) return drive(study::next_experiment_program(std::move(s), o.next_experiment));
    if (s.method == study::CalibrationMethod::mcmc) return drive(study::calibration_posterior_program(std::move(s)));
    return drive(study::calibration_fit_program(std::move(s)));
  });
}

const RegisterCommand calibrate_command{
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
      app.add_option("--starts", o->overrides.starts, "Independent starts of an NLopt first search (--algorithm), fanned out over ranks")
          ->check(CLI::Range(1, kMaxStarts));
      app.add_option("--max-evaluations", o->overrides.max_evaluations,
                     "Simulations per start of an NLopt first search (--algorithm), and per profile point (--profile)")
          ->check(CLI::Range(1, kMaxEvaluations));
      app.add_option("--max-iterations", o->overrides.max_iterations,
                     "Least-squares iterations (Jacobians) at most; default 10 + 5 per fitted parameter")
          ->check(CLI::Range(1, kMaxEvaluations));
      app.add_flag("--profile", o->overrides.profile,
                   "After the fit: profile-likelihood intervals of every fitted parameter (the others "
                   "re-optimised along a grid), a PNG each; says when a parameter is not identifiable");
      app.add_option("--method", o->overrides.method, "optimize (default) or mcmc")
          ->check(CLI::IsMember({"optimize", "mcmc"}));
      app.add_option("--walkers", o->overrides.walkers,
                     "mcmc: chains of the independence sampler, or ensemble walkers (even, >= 2 x sampled parameters)")
          ->check(CLI::Range(2, kMaxWalkers));
      app.add_option("--steps", o->overrides.steps, "mcmc: steps at most")->check(CLI::Range(1L, kMaxSteps));
      app.add_option("--discard", o->overrides.discard, "mcmc: burn-in steps left out of the summaries")
          ->check(CLI::Range(0L, kMaxSteps));
      app.add_option("--next-experiment", o->next_experiment,
                     "Rank the candidate experiments of this JSON file by the 95 % interval each parameter is "
                     "expected to have once their curve is added (after fitting the study's data); writes the "
                     "table (default results/<name>_next_experiment.h5)")
          ->check(CLI::ExistingFile);
      add_study_flags(app, o->run);
      return [o, &app] { return run_calibrate_command(app, *o); };
    },
    Processes::kMany};

}  // namespace
}  // namespace rover::cli
