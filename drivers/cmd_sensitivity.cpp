// `rover sensitivity`: global sensitivity analysis (Sobol' indices with
// bootstrap intervals, along time too; Morris screening) of the rover or of an
// analytic test model. See study/studies/sensitivity.hpp for the formats.
#include "drivers/command_registry.hpp"
#include "drivers/study_options.hpp"
#include "study/studies/sensitivity.hpp"

namespace rover::cli {
namespace {

constexpr long long kMinSensitivitySamples = 2, kMaxSensitivitySamples = 10'000'000;

struct SensitivityOptions {
  std::string study_path;
  std::optional<long long> samples;
  study::StudyRunOptions run;
};

study::StudyProgram<study::SensitivityResult> load(const SensitivityOptions& o) {
  return study::sensitivity_program(study::load_sensitivity_study(o.study_path, {o.samples, std::nullopt}));
}

const RegisterCommand sensitivity_command{
    55, "sensitivity", "Global sensitivity: Sobol' indices with confidence intervals (also along time), Morris screening",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<SensitivityOptions>();
      app.footer(std::string(
          "Sobol': the pick-freeze design A, B, A_B^(i) (N (d + 2) runs; second_order adds B_A^(i)),\n"
          "first-order indices by Saltelli (2010), total by Jansen (1999), bootstrap intervals; for\n"
          "every QoI, and along time for every channel. Morris: r one-at-a-time trajectories on a\n"
          "p-level grid; mu, mu*, sigma with bootstrap intervals and the ranking. A failed run drops\n"
          "its whole pick-freeze group (or trajectory) and the study says where runs failed.\n"
          "PCE (\"method\": \"pce\"): a sparse polynomial chaos fitted on N runs of an LHS or Sobol'\n"
          "design; S1 and ST in closed form with bootstrap intervals and the leave-one-out Q2, per\n"
          "QoI and along time per channel (a failed run is left out of the fit alone).\n"
          "\"model\": \"ishigami\" | \"sobol_g\" | \"linear\" runs an analytic model with known indices.\n"
          "A constant QoI's indices are marked undefined. Writes the figure <out>_summary.png;\n"
          "--plots all adds one figure per QoI and channel.\n\n"
          "Examples:\n"
          "  rover sensitivity --study configs/studies/sobol_ishigami.json\n"
          "  mpirun -np 2 rover sensitivity --study configs/studies/sobol_drop.json\n"
          "  mpirun -np 2 rover sensitivity --study configs/studies/pce_drop.json\n"
          "  mpirun -np 2 rover sensitivity --study configs/studies/morris_drop.json --out results/m.h5\n\n") +
          kMpiFooter);
      app.add_option("--study", o->study_path, "Study file (configs/studies/*.json, type sensitivity)")
          ->required()->check(CLI::ExistingFile);
      app.add_option("--samples", o->samples,
                     "Override the Sobol' base sample count N (runs: N (d + 2)), or the runs of a PCE study; 2 to 1e7")
          ->check(CLI::Range(kMinSensitivitySamples, kMaxSensitivitySamples));
      add_study_flags(app, o->run);
      return [o, &app] { return run_study_command(app, o->run, o->study_path, [&] { return load(*o); }); };
    },
    Processes::kMany};

}  // namespace
}  // namespace rover::cli
