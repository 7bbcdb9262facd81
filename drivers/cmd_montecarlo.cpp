// `rover montecarlo`: Monte Carlo over any uncertain parameters of the rover
// and scenario (the preloads of paper Fig. 13d by default): bands of the output
// channels and summaries of the QoIs. See study/studies/montecarlo.hpp for the formats.
#include <iostream>

#include "drivers/command_registry.hpp"
#include "drivers/study_options.hpp"
#include "study/studies/montecarlo.hpp"
#include "study/runtime/mpi_session.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::cli {
namespace {

struct MonteCarloOptions {
  std::string study_path;
  std::optional<long long> samples;
  std::string seed;  // read as the JSON "seed" is: 0 .. 2^64 - 1 exactly
  study::StudyRunControl control;
};

int run_montecarlo_command(MonteCarloOptions& o) {
  study::MpiSession mpi(nullptr, nullptr);
  FlagChecks checks;
  const std::uint64_t seed = o.seed.empty() ? 0 : checks.seed("--seed", o.seed);
  check_study_output(checks, o.control, o.study_path);
  checks.throw_if_any();
  study::MonteCarloStudy s = study::load_montecarlo_study(o.study_path);
  std::string changed;
  if (o.samples) {
    if (*o.samples < 1 || *o.samples > 100'000'000)
      throw std::invalid_argument("--samples must be from 1 to 1e8, got " + std::to_string(*o.samples));
    if (s.spec.design.type == study::DesignType::kGrid)
      throw std::invalid_argument("--samples does not apply to a grid design (its size is the product of its levels)");
    s.spec.design.samples = static_cast<int>(*o.samples);
    changed += " --samples " + std::to_string(*o.samples);
  }
  if (!o.seed.empty()) {
    s.spec.design.seed = seed;
    changed += " --seed " + std::to_string(seed);
  }
  // Options that change results are part of the checkpoint's fingerprint.
  s.spec.fingerprint = study::extend_fingerprint(
      s.spec.fingerprint, "samples " + std::to_string(s.spec.design.samples) + " seed " + std::to_string(s.spec.design.seed));
  o.control.resume_command = "rover montecarlo --study " + o.study_path + changed +
                             (o.control.results_path.empty() ? "" : " --out " + o.control.results_path) + " --resume";
  if (o.control.progress_interval_s < 1)
    throw std::invalid_argument("--progress-interval must be at least 1 s, got " +
                                std::to_string(o.control.progress_interval_s));
  if (mpi.rank() == 0)
    std::cerr << "montecarlo: " << s.spec.design.samples << " runs of " << s.spec.model->describe() << " over "
              << s.spec.inputs.size() << " inputs (" << study::design_type_name(s.spec.design.type) << ", seed "
              << s.spec.design.seed << ") on " << mpi.size() << " rank(s)\n";
  const study::InterruptGuard interrupts;
  return run_interruptible("montecarlo", [&] {
    study::run_montecarlo(s, o.control);
    return 0;
  });
}

const RegisterCommand registration{
    50, "montecarlo", "Monte Carlo over uncertain parameters: bands of output channels, QoI summaries (Fig. 13d)",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<MonteCarloOptions>();
      app.footer(std::string(
          "The study file names the uncertain parameters and their distributions, the design\n"
          "(monte_carlo, latin_hypercube, sobol, grid), the QoIs and the channels (docs/\n"
          "configuration.md). Sample i depends only on (seed, i). Writes /inputs, /qoi/<name>,\n"
          "/summary/<qoi> (mean, sd and quantiles with confidence intervals), /curves/<channel>,\n"
          "/bands/<channel>/{mean,std,lower,upper,p00135,p99865}, /samples/{status,message}, and PNGs\n"
          "of the bands, the QoI histograms and the convergence of mean and sd.\n\n"
          "Examples:\n"
          "  rover montecarlo --study configs/studies/preload_mc.json --samples 200\n"
          "  mpirun -np 4 rover montecarlo --study configs/studies/preload_mc.json --out results/mc.h5\n"
          "  rover montecarlo --study configs/studies/preload_mc.json --resume\n\n") + kMpiFooter);
      app.add_option("--study", o->study_path, "Study file (configs/studies/*.json, type montecarlo)")
          ->required()->check(CLI::ExistingFile);
      app.add_option("--samples", o->samples, "Override the number of samples N");
      app.add_option("--seed", o->seed, "Override the random seed, an integer from 0 to 2^64 - 1");
      add_study_control(app, o->control);
      return [o] { return run_montecarlo_command(*o); };
    }};

}  // namespace
}  // namespace rover::cli
