// `rover synthesize`: a synthetic "measured" drop curve (t,z CSV) made by the
// model at known parameters, with Gaussian measurement noise and an unknown
// time offset, for testing calibrations. Clearly labelled SYNTHETIC.
#include <iostream>
#include <sstream>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>

#include "core/metrics.hpp"
#include "drivers/command_registry.hpp"
#include "drivers/options.hpp"
#include "io/csv.hpp"
#include "io/scenario_config.hpp"

namespace rover::cli {
namespace {

struct SynthesizeOptions {
  std::string scenario = "configs/scenarios/drop_horizontal.json";
  std::string out;
  InputOverrides overrides;
  double noise_m = 1e-4, offset_s = 0.05, rate_hz = 500.0;
  long long seed = 7;
};

int run_synthesize(const SynthesizeOptions& o) {
  if (o.out.empty()) throw std::invalid_argument("--out is required");
  if (!(o.rate_hz > 0) || !(o.noise_m >= 0)) throw std::invalid_argument("--rate must be positive and --noise not negative");
  const io::ScenarioSetup setup = io::load_scenario(o.scenario);
  const ModelInputs in = apply_overrides(o.overrides, setup.inputs);
  const Trajectory tr = simulate(setup.model, setup.scenario, in);
  if (!tr.ok()) throw std::runtime_error("the simulation failed: " + tr.message);
  boost::random::mt19937_64 engine(static_cast<std::uint64_t>(o.seed));
  boost::random::normal_distribution<double> noise(0.0, o.noise_m);
  // Data clock: t_d = t_sim + offset, from 0 to the end of the run; before the
  // release the rover hangs at its initial height.
  std::vector<double> t, z;
  const double end = setup.scenario.duration_s + o.offset_s;
  for (int k = 0;; ++k) {
    const double td = k / o.rate_hz;
    if (td > end - 1e-12 || td > setup.scenario.duration_s) break;
    t.push_back(td);
    z.push_back(interpolate(tr.t, tr.B_l_z, td - o.offset_s) + (o.noise_m > 0 ? noise(engine) : 0.0));
  }
  std::ostringstream comment;
  comment << "SYNTHETIC measured drop curve, NOT experimental data.\n"
          << "Made by `rover synthesize` from " << o.scenario << " at f = " << in.sharpness_f
          << ", c_q = " << in.damping_c_q << ", M0 = [";
  for (int j = 0; j < kNumSJoints; ++j) comment << (j ? ", " : "") << in.preload_Nm[j];
  comment << "],\nGaussian noise sd " << o.noise_m << " m (seed " << o.seed << "), time offset "
          << o.offset_s << " s (t_data = t_release + offset), " << o.rate_hz << " Hz.\n"
          << "Columns: t [s], z [m] = world z of the left bogie pin B_l.";
  io::write_csv(o.out, {"t", "z"}, {t, z}, comment.str());
  std::cerr << "synthesize: wrote " << t.size() << " points to " << o.out << "\n";
  return 0;
}

const RegisterCommand registration{
    70, "synthesize", "Make a SYNTHETIC measured drop curve (t,z CSV) with noise and a time offset",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<SynthesizeOptions>();
      app.footer(
          "The paper's measurements are not public; this makes stand-ins with known answers for\n"
          "calibration tests. The file's comment header records every parameter.\n\n"
          "Example (the shipped configs/data/drop_horizontal_synthetic.csv):\n"
          "  rover synthesize --scenario configs/scenarios/drop_horizontal.json --cq 0.25 \\\n"
          "      --noise 1e-4 --offset 0.05 --rate 500 --seed 7 --out configs/data/drop_horizontal_synthetic.csv");
      app.add_option("--scenario", o->scenario, "Scenario file")->capture_default_str()->check(CLI::ExistingFile);
      app.add_option("--out", o->out, "CSV file to write")->required();
      add_input_overrides(app, o->overrides);
      app.add_option("--noise", o->noise_m, "Measurement noise standard deviation [m]")->capture_default_str();
      app.add_option("--offset", o->offset_s, "Time of the release on the data clock [s]")->capture_default_str();
      app.add_option("--rate", o->rate_hz, "Sample rate of the data [Hz]")->capture_default_str();
      app.add_option("--seed", o->seed, "Noise seed")->capture_default_str();
      return [o] { return run_synthesize(*o); };
    }};

}  // namespace
}  // namespace rover::cli
