// `rover sensitivity`: global sensitivity analysis (Sobol' indices with
// bootstrap intervals, along time too; Morris screening) of the rover or of an
// analytic test model. See study/studies/sensitivity.hpp for the formats.
#include <iostream>

#include "drivers/command_registry.hpp"
#include "drivers/study_options.hpp"
#include "study/runtime/mpi_session.hpp"
#include "study/studies/sensitivity.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::cli {
namespace {

struct SensitivityOptions {
  std::string study_path;
  std::optional<long long> samples;
  study::StudyRunControl control;
};

int run_sensitivity_command(SensitivityOptions& o) {
  study::MpiSession mpi(nullptr, nullptr);
  FlagChecks checks;
  check_study_output(checks, o.control, o.study_path);
  checks.throw_if_any();
  study::SensitivityStudy s = study::load_sensitivity_study(o.study_path);
  if (o.samples) {
    if (s.method == study::SensitivityMethod::kMorris)
      throw std::invalid_argument("--samples sets the Sobol' base sample count or the PCE runs; a Morris study has trajectories");
    if (*o.samples < 2 || *o.samples > 10'000'000)
      throw std::invalid_argument("--samples must be from 2 to 1e7, got " + std::to_string(*o.samples));
    if (s.method == study::SensitivityMethod::kPce) {
      study::set_pce_runs(s, static_cast<int>(*o.samples));
    } else {
      s.layout.base_samples = static_cast<int>(*o.samples);
      s.spec.design.samples = s.layout.total_runs();
      s.spec.fingerprint = study::extend_fingerprint(s.spec.fingerprint, "samples " + std::to_string(*o.samples));
    }
  }
  o.control.resume_command = "rover sensitivity --study " + o.study_path +
                             (o.samples ? " --samples " + std::to_string(*o.samples) : std::string()) +
                             (o.control.results_path.empty() ? "" : " --out " + o.control.results_path) + " --resume";
  if (mpi.rank() == 0)
    std::cerr << "sensitivity: " << (s.method == study::SensitivityMethod::kSobol    ? "Sobol'"
                                : s.method == study::SensitivityMethod::kMorris ? "Morris"
                                                                                 : "polynomial chaos") << ", "
              << s.spec.inputs.size() << " inputs, " << s.spec.design.samples << " runs of " << s.spec.model->describe()
              << " on " << mpi.size() << " rank(s)\n";
  const study::InterruptGuard interrupts;
  return run_interruptible("sensitivity", [&] {
    study::run_sensitivity(s, o.control);
    return 0;
  });
}

const RegisterCommand registration{
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
          "\"model\": \"ishigami\" | \"sobol_g\" | \"linear\" runs an analytic model with known indices.\n\n"
          "Examples:\n"
          "  rover sensitivity --study configs/studies/sobol_ishigami.json\n"
          "  mpirun -np 2 rover sensitivity --study configs/studies/sobol_drop.json\n"
          "  mpirun -np 2 rover sensitivity --study configs/studies/pce_drop.json\n"
          "  mpirun -np 2 rover sensitivity --study configs/studies/morris_drop.json --out results/m.h5\n\n") +
          kMpiFooter);
      app.add_option("--study", o->study_path, "Study file (configs/studies/*.json, type sensitivity)")
          ->required()->check(CLI::ExistingFile);
      app.add_option("--samples", o->samples, "Override the Sobol' base sample count N (runs: N (d + 2)), or the runs of a PCE study");
      add_study_control(app, o->control);
      return [o] { return run_sensitivity_command(*o); };
    }};

}  // namespace
}  // namespace rover::cli
