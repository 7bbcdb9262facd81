// `rover simulate`: one scenario, written as HDF5 (+ optional CSV) and PNG plots.
//
// Flags are checked before the scenario is loaded. Two kinds of silent
// trouble get a warning on stderr: friction gammas that miss the fit quality
// bar of docs/model.md §6 (also recorded in the file, see
// io/trajectory_io.hpp), and a result whose chassis origin G ends below the
// terrain (the wheels went through the ground, e.g. after a drop from metres).
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "core/friction_synthesis.hpp"
#include "drivers/command_registry.hpp"
#include "drivers/held_outputs.hpp"
#include "drivers/interruptible_outputs.hpp"
#include "drivers/interruptible_simulation.hpp"
#include "drivers/options.hpp"
#include "io/output_target.hpp"
#include "io/trajectory_io.hpp"

namespace rover::cli {
namespace {

struct SimulateOptions {
  std::string scenario;
  std::string out;
  std::string csv;
  bool no_plot = false;
  InputOverrides overrides;
  std::string integrator;
};

// The stem of the plots beside the HDF5 output: results/a.h5 -> results/a.
std::string plot_stem(const std::string& out) {
  return out.substr(0, out.size() - std::filesystem::path(out).extension().string().size());
}

// The HDF5 output `out` (named by `out_flag`: "--out" or "--out (default)")
// and the plots beside it can be written.
void check_output_targets(const SimulateOptions& o, const std::string& out_flag, const std::string& out,
                          FlagChecks& checks) {
  checks.output_file(out_flag, out, /*regular_only=*/true);
  if (!o.no_plot) {
    checks.plots_beside(out_flag, out);
    checks.plotter("the plot of " + out_flag, "pass --no-plot");
  }
}

// `out` is an .h5 name, and a different file from --csv and from each plot
// (<stem>.png, <stem>_attitude.png), so that no output replaces another.
// Checked after check_outputs_over_inputs: an input the output would destroy
// is named first.
void check_output_names(const SimulateOptions& o, const std::string& out_flag, const std::string& out) {
  FlagChecks checks;
  if (const std::string refusal = io::extension_only_refusal(out); !refusal.empty()) {
    checks.add(out_flag + " '" + out + "' " + refusal);
    checks.throw_if_any();
  }
  if (std::filesystem::path(out).extension() != ".h5") {
    checks.add(out_flag + " '" + out + "' must end in .h5 (an HDF5 file)");
    checks.throw_if_any();  // its plot has its name then: said once
  }
  std::vector<FlagChecks::NamedOutput> outputs{{out_flag, out}, {"--csv", o.csv}};
  if (!o.no_plot) {
    const std::string plot_of = "the plot of " + out_flag + " '" + out + "',";
    outputs.push_back({plot_of, plot_stem(out) + ".png"});
    outputs.push_back({plot_of, plot_stem(out) + "_attitude.png"});
  }
  checks.distinct_outputs(outputs);
  checks.throw_if_any();
  checks.output_format("--csv", o.csv, "CSV", ".csv");  // after: another output it would replace is named first
  checks.throw_if_any();
}

// Checks every flag before the scenario is loaded.
void check_flags(const SimulateOptions& o) {
  FlagChecks checks;
  check_overrides(o.overrides, checks);
  check_integrator_flag(checks, o.integrator);
  checks.output_file("--csv", o.csv);
  if (!o.out.empty()) check_output_targets(o, "--out", o.out, checks);
  checks.throw_if_any();
}

// Checks, before the run, that no output replaces a file the command reads:
// the scenario and the files it names.
// `out_flag` names the HDF5 output: "--out", or "--out (default)".
void check_outputs_over_inputs(const SimulateOptions& o, const io::ScenarioSetup& setup, const std::string& out_flag,
                               const std::string& out) {
  io::InputFiles inputs;
  inputs.add(o.scenario, "--scenario");
  inputs.add_all(setup.files);
  FlagChecks checks;
  checks.not_an_input(out_flag, out, inputs,
                      o.no_plot ? io::WrittenBeside::kTemporaries : io::WrittenBeside::kTemporariesAndPlots);
  checks.not_an_input("--csv", o.csv, inputs, io::WrittenBeside::kTemporaries);  // <csv>.partial too
  checks.throw_if_any();
}

// A failed run never replaces an earlier output: its record (the state up to
// the failure and why) goes to --out only when nothing is there, and no CSV
// or plot is written. Exit status 2.
int record_failed_run(const SimulateOptions& o, const std::string& out, const Trajectory& tr,
                      const io::ScenarioSetup& setup, const ModelInputs& inputs, InterruptibleOutputs& outputs) {
  std::cerr << "simulate: the run failed: " << tr.message << "\n";
  for (const std::string& unwritten : {o.csv, plot_stem(out) + ".png", plot_stem(out) + "_attitude.png"})
    outputs.dropped(unwritten);
  if (std::error_code error; std::filesystem::exists(out, error)) {
    std::cerr << "simulate: the earlier result " << out << " was kept and nothing was written (give a new "
              << "--out to keep the failed run's record)\n";
    return 2;
  }
  if (!io::write_trajectory_hdf5(out, tr, setup, inputs, outputs.stop()))
    outputs.interrupted_while("writing " + out);
  outputs.written(out);
  std::cerr << "simulate: wrote the failed run's record to " << out
            << (o.csv.empty() && o.no_plot ? "" : "; no CSV or plot of a failed run") << "\n";
  return 2;
}

// Whether the rover travelled (obstacle runs, turns): such a run also gets
// plots of B_r, G and the attitude; a drop test only of B_l z.
bool travelled(const Trajectory& tr) {
  const auto last = tr.q.rows() - 1;
  return last > 0 &&
         std::hypot(tr.q(last, coord::x) - tr.q(0, coord::x), tr.q(last, coord::y) - tr.q(0, coord::y)) > 0.01;
}

// Writes the successful run `tr`: HDF5, the CSV if asked for, the plots.
int write_run(const SimulateOptions& o, const std::string& out, const Trajectory& tr, const io::ScenarioSetup& setup,
              const ModelInputs& inputs, InterruptibleOutputs& outputs) {
  if (!io::write_trajectory_hdf5(out, tr, setup, inputs, outputs.stop()))
    outputs.interrupted_while("writing " + out);
  std::cerr << "simulate: ok; wall " << tr.wall_time_s << " s, " << tr.rhs_evaluations << " right-hand sides, "
            << tr.steps << " steps; wrote " << out << "\n";
  outputs.written(out);
  if (!o.csv.empty()) {
    if (!io::write_trajectory_csv(o.csv, tr, outputs.stop())) outputs.interrupted_while("writing " + o.csv);
    std::cerr << "simulate: wrote " << o.csv << "\n";
    outputs.written(o.csv);
  }
  if (o.no_plot) return 0;
  const std::string stem = plot_stem(out);
  const bool obstacle = travelled(tr);
  if (!obstacle) outputs.dropped(stem + "_attitude.png");
  try {
    for (const auto& png : io::write_trajectory_plots(stem, tr, setup.scenario.name, obstacle, outputs.stop())) {
      std::cerr << "simulate: wrote " << png << "\n";
      outputs.written(png);
    }
  } catch (const study::StudyInterrupted&) {
    throw;
  } catch (const std::exception& e) {
    outputs.stop_if_signalled();  // gnuplot ended by the same Ctrl-C: said as the interrupt it is
    std::cerr << "simulate: warning: no plot (" << e.what() << "); the data are in " << out << "\n";
    return 0;
  }
  outputs.stop_if_signalled();
  return 0;
}

int run_simulate(const SimulateOptions& o) {
  check_flags(o);
  io::ScenarioSetup setup = io::load_scenario(o.scenario);
  // A different method comes with its own default tolerances (see default_integrator_settings).
  if (!o.integrator.empty()) setup.scenario.integrator = default_integrator_settings(integrator_from_name(o.integrator));
  const ModelInputs inputs = apply_overrides(o.overrides, setup.inputs);
  const std::string out =
      o.out.empty() ? "results/" + setup.scenario.name + ".h5" : o.out;
  if (o.out.empty()) {
    FlagChecks default_out;
    check_output_targets(o, "--out (default)", out, default_out);
    default_out.throw_if_any();
  }
  const std::string out_flag = o.out.empty() ? "--out (default)" : "--out";
  check_outputs_over_inputs(o, setup, out_flag, out);
  check_output_names(o, out_flag, out);
  const FrictionParameters& friction = setup.model.parameters.friction;
  if (const FrictionFitQuality fit = friction_fit_quality(friction.gammas, friction); !fit.acceptable)
    std::cerr << "simulate: warning: the friction gammas miss the fit quality bar (RMS " << fit.rms
              << " against < " << kFrictionMaxRms << ", peak mu " << fit.peak_mu << " against mu_s "
              << friction.mu_static << " within " << 100 * kFrictionMaxPeakError
              << " %); check `rover friction` for these mu_s, v_s, mu_k, v_k (recorded as "
                 "friction_fit_acceptable = 0 in the file)\n";
  // From the run to the last plot a signal ends the command with a word and
  // no partial file; the locks go as the exception unwinds.
  InterruptibleOutputs outputs({out, o.csv, o.no_plot ? "" : plot_stem(out) + ".png",
                                o.no_plot ? "" : plot_stem(out) + "_attitude.png"});
  HeldOutputs held;  // the run begins: its folders are made, and no other process writes its outputs
  held.hold(out_flag, out);
  held.hold("--csv", o.csv);

  std::cerr << "simulate: " << setup.scenario.name << ", " << setup.scenario.duration_s << " s, "
            << integrator_name(setup.scenario.integrator.method) << ", f = " << inputs.sharpness_f
            << ", c_q = " << inputs.damping_c_q << "\n";
  SimulationObserver observer;
  observer.progress = [&](double t) {
    std::cerr << "  t = " << t << " / " << setup.scenario.duration_s << " s\n";
  };
  const Trajectory tr = simulate_interruptibly(setup.model, setup.scenario, inputs, observer);
  for (const std::string& note : {no_wheel_touched_note(tr), chassis_through_ground_note(tr, setup.model.terrain)})
    if (!note.empty()) std::cerr << "simulate: warning: " << note << "\n";
  outputs.stop_if_signalled();
  if (!tr.ok()) return record_failed_run(o, out, tr, setup, inputs, outputs);
  return write_run(o, out, tr, setup, inputs, outputs);
}

const RegisterCommand simulate_command{
    40, "simulate", "Simulate one scenario (drop test, obstacle run, ...) and write HDF5, CSV and PNG",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<SimulateOptions>();
      app.footer(
          "Writes HDF5 datasets /t /B_l_z /B_r_z /G_z /pitch /roll /q (T x 23) /u (T x 23) /Fn (T x 4)\n"
          "with attributes recording every parameter, the integrator, wall time and right-hand-side\n"
          "evaluations, and PNG plots next to it (<out>.png; obstacle runs also <out>_attitude.png).\n"
          "Exit status 2 if the run failed (diverged, step underflow, time budget): the file records why,\n"
          "with no CSV or plot; if --out held an earlier result, that is kept and nothing is written.\n\n"
          "Examples:\n"
          "  rover simulate --scenario configs/scenarios/drop_horizontal.json --out results/drop_horizontal.h5\n"
          "  rover simulate --scenario configs/scenarios/drop_skewed.json --cq 0.3 --f 1e3 --csv results/skewed.csv\n"
          "  rover simulate --scenario configs/scenarios/obstacle_v1.json --integrator rk4");
      app.add_option("--scenario", o->scenario, "Scenario file (configs/scenarios/*.json)")
          ->required()->check(CLI::ExistingFile);
      app.add_option("--out", o->out, "HDF5 output, ending in .h5 (default results/<scenario>.h5)");
      app.add_option("--csv", o->csv, "Also write the same columns as CSV to this file");
      app.add_flag("--no-plot", o->no_plot, "Do not write PNG plots");
      app.add_option("--integrator", o->integrator, "Override the scenario's integrator, with that method's default tolerances: " +
                         integrator_choices_text());
      add_input_overrides(app, o->overrides);
      return [o] { return run_simulate(*o); };
    }};

}  // namespace
}  // namespace rover::cli
