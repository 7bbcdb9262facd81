// `rover montecarlo`: 3-sigma bands of the drop response over the uncertain
// preloads (paper Fig. 13d). See study/montecarlo.hpp for the formats.
#include <iostream>

#include "drivers/command_registry.hpp"
#include "drivers/study_options.hpp"
#include "study/montecarlo.hpp"
#include "study/mpi_session.hpp"

namespace rover::cli {
namespace {

struct MonteCarloOptions {
  std::string study_path;
  std::optional<int> samples;
  std::optional<long long> seed;
  study::StudyRunControl control;
};

int run_montecarlo_command(const MonteCarloOptions& o) {
  study::MpiSession mpi(nullptr, nullptr);
  study::MonteCarloStudy s = study::load_montecarlo_study(o.study_path);
  if (o.samples) {
    if (*o.samples <= 0) throw std::invalid_argument("--samples must be positive");
    s.samples = *o.samples;
  }
  if (o.seed) s.seed = static_cast<std::uint64_t>(*o.seed);
  if (mpi.rank() == 0)
    std::cerr << "montecarlo: " << s.samples << " samples of " << s.common.setup.scenario.name
              << " on " << mpi.size() << " rank(s), seed " << s.seed << "\n";
  study::run_montecarlo(s, o.control);
  return 0;
}

const RegisterCommand registration{
    50, "montecarlo", "Monte Carlo over the 8 uncertain preloads M0: 3-sigma band of B_l z(t) (Fig. 13d)",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<MonteCarloOptions>();
      app.footer(std::string(
          "Draws M0 ~ Normal(mean, sd) (configs/rover.json) for each sample; sample i depends only\n"
          "on (seed, i). Writes /samples/M0, /t, /curves/B_l_z, /band/{mean,std,lower,upper,p00135,\n"
          "p99865}, per-sample deflection, at-rest value and status, and a PNG of the band.\n\n"
          "Examples:\n"
          "  rover montecarlo --study configs/studies/preload_mc.json --samples 200\n"
          "  mpirun -np 4 rover montecarlo --study configs/studies/preload_mc.json --out results/mc.h5\n"
          "  rover montecarlo --study configs/studies/preload_mc.json --resume\n\n") + kMpiFooter);
      app.add_option("--study", o->study_path, "Study file (configs/studies/*.json, type montecarlo)")
          ->required()->check(CLI::ExistingFile);
      app.add_option("--samples", o->samples, "Override the number of samples N");
      app.add_option("--seed", o->seed, "Override the random seed");
      add_study_control(app, o->control);
      return [o] { return run_montecarlo_command(*o); };
    }};

}  // namespace
}  // namespace rover::cli
