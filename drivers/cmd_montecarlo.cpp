// `rover montecarlo`: Monte Carlo over any uncertain parameters of the rover
// and scenario (the preloads of paper Fig. 13d by default): bands of the output
// channels and summaries of the QoIs. See study/studies/montecarlo.hpp for the formats.
#include "drivers/command_registry.hpp"
#include "drivers/study_options.hpp"
#include "study/studies/montecarlo.hpp"

namespace rover::cli {
namespace {

constexpr long long kMinMonteCarloSamples = 2;  // an sd and a band need 2
constexpr long long kMaxMonteCarloSamples = 100'000'000;

struct MonteCarloOptions {
  std::string study_path;
  std::optional<long long> samples;
  std::string seed;  // read as the JSON "seed" is: 0 .. 2^64 - 1 exactly
  study::StudyRunOptions run;
};

study::StudyProgram<study::MonteCarloResult> load(const MonteCarloOptions& o) {
  FlagChecks checks;
  const std::uint64_t seed = o.seed.empty() ? 0 : checks.seed("--seed", o.seed);
  checks.throw_if_any();
  study::DesignOverrides overrides{o.samples, std::nullopt};
  if (!o.seed.empty()) overrides.seed = seed;
  return study::montecarlo_program(study::load_montecarlo_study(o.study_path, overrides));
}

const RegisterCommand montecarlo_command{
    50, "montecarlo", "Monte Carlo over uncertain parameters: bands of output channels, QoI summaries (Fig. 13d)",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<MonteCarloOptions>();
      app.footer(std::string(
          "The study file names the uncertain parameters and their distributions, the design\n"
          "(monte_carlo, latin_hypercube, sobol, grid), the QoIs and the channels (docs/\n"
          "configuration.md). Sample i depends only on (seed, i). Writes /inputs, /qoi/<name>,\n"
          "/summary/<qoi> (mean, sd and quantiles with confidence intervals), /curves/<channel>,\n"
          "/bands/<channel>/{mean,std,lower,upper,p00135,p99865}, /samples/{status,message}, and the\n"
          "figure <out>_summary.png (bands, QoI histograms, running means); --plots all adds one PNG\n"
          "per band, histogram and convergence of mean and sd.\n\n"
          "Examples:\n"
          "  rover montecarlo --study configs/studies/preload_mc.json --samples 200\n"
          "  mpirun -np 4 rover montecarlo --study configs/studies/preload_mc.json --out results/mc.h5\n"
          "  rover montecarlo --study configs/studies/preload_mc.json --resume\n\n") + kMpiFooter);
      app.add_option("--study", o->study_path, "Study file (configs/studies/*.json, type montecarlo)")
          ->required()->check(CLI::ExistingFile);
      app.add_option("--samples", o->samples, "Override the number of samples N, from 2 (an sd needs 2) to 1e8")
          ->check(CLI::Range(kMinMonteCarloSamples, kMaxMonteCarloSamples));
      app.add_option("--seed", o->seed, "Override the random seed, an integer from 0 to 2^64 - 1");
      add_study_flags(app, o->run);
      return [o, &app] { return run_study_command(app, o->run, o->study_path, [&] { return load(*o); }); };
    },
    Processes::kMany};

}  // namespace
}  // namespace rover::cli
