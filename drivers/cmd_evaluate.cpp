// `rover evaluate`: batch evaluation of a design CSV (one run per row), the
// interface other UQ tools drive the model through. See study/studies/evaluate.hpp.
// The flags are checked before any row is read: QoI and channel names, the
// integrator, and an --out that is writable and is neither input file.
#include <algorithm>
#include <iostream>
#include <sstream>

#include "drivers/command_registry.hpp"
#include "drivers/options.hpp"
#include "drivers/study_options.hpp"
#include "study/model/qoi.hpp"
#include "study/studies/evaluate.hpp"

namespace rover::cli {
namespace {

// A name given twice in a list flag: every run would compute it twice, and
// the results would hold two columns of one name (an .h5 refuses the second
// after all the runs).
void refuse_repeated_names(FlagChecks& checks, const std::string& flag, const std::vector<std::string>& names) {
  for (auto it = names.begin(); it != names.end(); ++it)
    if (std::count(names.begin(), it, *it) == 1)  // its second mention
      checks.add(flag + ": '" + *it + "' is listed twice; give each name once");
}

struct EvaluateOptions {
  std::string qoi = "B_l_z_min,deflection", channels;
  study::EvaluateRequest request;
  study::StudyRunOptions run;
};

study::StudyProgram<study::EvaluateResult> load(EvaluateOptions& o) {
  FlagChecks checks;
  o.request.qoi_names = split_names("--qoi", o.qoi, checks);
  o.request.channel_names = split_names("--channels", o.channels, checks);
  o.request.out_path = o.run.results_path;
  for (const std::string& q : o.request.qoi_names) {
    try {
      study::qoi_kind_from_name(q);
    } catch (const std::invalid_argument& e) {
      checks.add("--qoi: " + std::string(e.what()));
    }
  }
  for (const std::string& c : o.request.channel_names) {
    try {
      study::channel_from_name(c);
    } catch (const std::invalid_argument& e) {
      checks.add("--channels: " + std::string(e.what()));
    }
  }
  refuse_repeated_names(checks, "--qoi", o.request.qoi_names);
  refuse_repeated_names(checks, "--channels", o.request.channel_names);
  if (o.request.qoi_names.empty() && o.request.channel_names.empty())
    checks.add("--qoi '" + o.qoi + "' names no quantity of interest (and no --channels are given): nothing to compute");
  check_integrator_flag(checks, o.request.integrator);
  checks.throw_if_any();
  return study::evaluate_program(study::load_evaluate(o.request));
}

const RegisterCommand evaluate_command{
    45, "evaluate", "Batch evaluation: one run per row of a design CSV -> QoIs per row (for Dakota, OpenTURNS, SALib)",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<EvaluateOptions>();
      app.footer(std::string(
          "The design CSV's header names the inputs (dotted config paths such as contact.k_g,\n"
          "bodies.chassis.mass, scenario.initial_q.z, or the aliases f, c_q, M0_11 .. M0_42); each row\n"
          "is one run, every other parameter at its configured value. Every row is validated before\n"
          "any run. The output (.csv or .h5) holds, in row order, the inputs, each QoI, the status\n"
          "(0 = ok) and the message of every run, and the figure <out>_summary.png shows each QoI's\n"
          "histogram (--plots none: no figure). Exit code 2 if some runs failed.\n\n"
          "Examples:\n"
          "  rover evaluate --scenario configs/scenarios/drop_horizontal.json --design X.csv \\\n"
          "      --qoi B_l_z_min,deflection --out Y.csv\n"
          "  mpirun -np 4 rover evaluate --scenario configs/scenarios/obstacle_v1.json --design X.csv \\\n"
          "      --qoi B_r_rise,G_rise --channels B_r_z --out results/Y.h5 --integrator rosenbrock\n\n") +
          kMpiFooter);
      app.add_option("--scenario", o->request.scenario_path, "Scenario file (configs/scenarios/*.json)")
          ->required()->check(CLI::ExistingFile);
      app.add_option("--design", o->request.design_path, "Design CSV: header of parameter names, one row per run")
          ->required()->check(CLI::ExistingFile);
      app.add_option("--qoi", o->qoi, "Comma-separated QoIs (B_l_z_min, t_min, deflection, at_rest, rebound_peak, "
                                      "settling_time, max_abs_pitch, max_abs_roll, max_wheel_load, B_r_rise, "
                                      "G_rise, lateral_drift, yaw_drift)")
          ->capture_default_str();
      app.add_option("--channels", o->channels, "Comma-separated curves to store (.h5 only): B_l_z, B_r_z, G_z, "
                                                "pitch, roll, Fn_1 .. Fn_4");
      app.add_option("--out", o->run.results_path, "Output file, .csv or .h5")->required();
      app.add_option("--integrator", o->request.integrator,
                     "Replace the scenario's integrator by this method at its default tolerances: " +
                         integrator_choices_text());
      app.add_flag("--resume", o->run.resume, "Continue from <out>.checkpoint: only the missing rows run");
      app.add_flag("--restart", o->run.restart, "Discard <out>.checkpoint of an interrupted evaluation and start afresh");
      add_dry_run_flag(app, o->run);
      add_plots_flags(app, o->run);
      add_progress_flags(app, o->run);
      return [o, &app] { return run_study_command(app, o->run, "", [&] { return load(*o); }); };
    },
    Processes::kMany};

}  // namespace
}  // namespace rover::cli
