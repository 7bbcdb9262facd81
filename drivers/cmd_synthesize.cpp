// `rover synthesize`: a synthetic "measured" drop curve (t,z CSV) made by the
// model at known parameters, with Gaussian measurement noise and an unknown
// time offset, for testing calibrations. Clearly labelled SYNTHETIC.
// Any scenario file, any channel a calibration's "data" entry may name
// (study/studies/calibration.hpp: B_l_z, B_r_z, G_z) and any integrator; the file's
// comment header records all of them. Every bad flag is reported before the
// simulation, and a sample count whose file would be absurdly large is
// refused with its size.
#include <algorithm>
#include <cmath>
#include <optional>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>

#include "core/accuracy_choice.hpp"
#include "core/metrics.hpp"
#include "drivers/command_registry.hpp"
#include "drivers/held_outputs.hpp"
#include "drivers/interruptible_outputs.hpp"
#include "drivers/interruptible_simulation.hpp"
#include "drivers/options.hpp"
#include "io/csv.hpp"
#include "io/scenario_config.hpp"
#include "study/studies/calibration.hpp"

namespace rover::cli {
namespace {

constexpr const char* kDefaultScenario = "configs/scenarios/drop_horizontal.json";
// A line "t,z\n" of two shortest round-trip doubles: at most 2 x 24 + 2 bytes.
constexpr double kBytesPerLine = 50.0;
// A synthetic curve beyond 1 GB (2e7 points, 1 MHz over 20 s) is a mistake.
constexpr double kMaxCurveBytes = 1e9;
// The exit status of a run that failed, as `rover simulate`'s.
constexpr int kFailedRunStatus = 2;
// Synthetic data are the truth a fit is meant to recover: their integration
// error stays below this share of the noise sd (a tenth: it then moves a
// fitted parameter by a small part of its standard error), and below
// kNoiseFreeAccuracy_m for a curve without noise.
constexpr double kIntegrationErrorPerNoiseSd = 0.1;
constexpr double kNoiseFreeAccuracy_m = 1e-7;

struct SynthesizeOptions {
  std::string scenario = kDefaultScenario;
  std::string out;
  InputOverrides overrides;
  double noise_m = 1e-4, offset_s = 0.05, rate_hz = 500.0;
  std::string seed = "7";
  std::string channel = "B_l_z";
  std::string integrator;  // empty: the scenario's
  CLI::Option* scenario_option = nullptr;
  CLI::Option* offset_option = nullptr;
};

// Without --offset the release is this far into the data clock, or at half
// the run of a shorter scenario, so that the drop is in the data.
constexpr double kDefaultOffset_s = 0.05;
constexpr double kDefaultOffsetShareOfDuration = 0.5;

double default_offset(double duration_s) { return std::min(kDefaultOffset_s, kDefaultOffsetShareOfDuration * duration_s); }

// The data clock runs t_d = t_sim + offset from 0 to the end of the run: the
// number of points k / rate within the simulated span and the data's.
std::size_t data_point_count(double duration_s, double offset_s, double rate_hz) {
  const double end = duration_s + offset_s;
  std::size_t n = 0;
  for (double td = 0.0; !(td > end - 1e-12 || td > duration_s); td = static_cast<double>(n) / rate_hz) ++n;
  return n;
}

// The data points at or after the release (t_d >= offset).
std::size_t points_after_release(double duration_s, double offset_s, double rate_hz) {
  const std::size_t points = data_point_count(duration_s, offset_s, rate_hz);
  std::size_t after = 0;
  for (std::size_t k = 0; k < points; ++k) after += static_cast<double>(k) / rate_hz >= offset_s - 1e-12 ? 1 : 0;
  return after;
}

// The largest offset that leaves kMeasuredCurveMinRows points at or after the
// release: the time of that point counted back from the data's last.
double largest_offset(double duration_s, double rate_hz) {
  const std::size_t points = data_point_count(duration_s, duration_s, rate_hz);  // a positive offset: to the run's end
  if (points < io::kMeasuredCurveMinRows) return 0.0;
  return static_cast<double>(points - io::kMeasuredCurveMinRows) / rate_hz;
}

// Refuses a data clock that gives a curve rover compare and calibrate would
// refuse: too many or too few points, or a release after the run's end.
void check_data_clock(const SynthesizeOptions& o, double duration_s, const std::string& scenario_path) {
  if (const std::string problem = io::recording_size_problem(
          io::recorded_sample_count(duration_s, o.rate_hz), kBytesPerLine, kMaxCurveBytes);
      !problem.empty())
    throw CommandLineError({"--rate " + number_text(o.rate_hz) + " over the " +
                            number_text(duration_s) + " s of " + scenario_path +
                            ": " + problem + "; reduce --rate"});
  // A release more than the run before the data clock's start leaves no point within the run.
  if (!(duration_s + o.offset_s > 0.0))
    throw CommandLineError({"--offset " + number_text(o.offset_s) + " s puts the release before the data clock's "
                            "start by more than the " + number_text(duration_s) + " s of " + scenario_path +
                            ": no data point falls within the run; give an offset above -" +
                            number_text(duration_s) + " s (the release's time on the data clock)"});
  if (const std::size_t points = data_point_count(duration_s, o.offset_s, o.rate_hz);
      points < io::kMeasuredCurveMinRows)
    throw CommandLineError({"--rate " + number_text(o.rate_hz) + " Hz and --offset " + number_text(o.offset_s) +
                            " s over the " + number_text(duration_s) + " s of " + scenario_path +
                            " give " + std::to_string(points) + " data point(s); a measured curve needs at least " +
                            std::to_string(io::kMeasuredCurveMinRows) +
                            " (rover compare and calibrate refuse fewer): raise --rate"});
  // A release at or near the data's end: the points before it are the rover
  // hanging at rest, a curve with (almost) no drop in it.
  if (const std::size_t after = points_after_release(duration_s, o.offset_s, o.rate_hz);
      after < io::kMeasuredCurveMinRows)
    throw CommandLineError({"--offset " + number_text(o.offset_s) + " s leaves " + std::to_string(after) +
                            " data point(s) at or after the release: the data clock at " + number_text(o.rate_hz) +
                            " Hz runs to the end of the " + number_text(duration_s) + " s of " + scenario_path +
                            ", and a measured curve needs at least " + std::to_string(io::kMeasuredCurveMinRows) +
                            " points of the drop (before the release the rover hangs at rest); give an offset above -" +
                            number_text(duration_s) + " s and at most " +
                            number_text(largest_offset(duration_s, o.rate_hz)) + " s"});
}

// The integrator that makes the data: the one asked for if its measured
// error (core/accuracy_choice.hpp) is within the accuracy the noise asks,
// else the cheapest measured setting that is, said on stderr.
IntegratorSettings data_integrator(const IntegratorSettings& asked, const std::string& asked_by, double noise_m) {
  const double wanted_m = noise_m > 0.0 ? kIntegrationErrorPerNoiseSd * noise_m : kNoiseFreeAccuracy_m;
  const double accuracy_m = std::clamp(wanted_m, 2.0 * kMostAccuracy_m, 0.5 * kLeastAccuracy_m);
  const std::optional<double> expected = expected_error_m(asked);
  if (expected && *expected <= accuracy_m) return asked;
  const IntegratorChoice chosen = integrator_for_accuracy(accuracy_m);
  std::cerr << "synthesize: " << asked_by << " (" << study::describe_integrator(asked) << ") "
            << (expected ? "errs by up to " + number_text(*expected) + " m RMS on the paper's five scenarios"
                         : std::string("has no measured error"))
            << "; the data need an integration error below " << number_text(accuracy_m) << " m ("
            << (accuracy_m > wanted_m ? "the tightest the integrators are measured to reach; a tenth of the noise "
                                        "sd would be " + number_text(wanted_m) + " m"
                : noise_m > 0.0     ? "a tenth of the noise sd"
                                    : "noise-free data")
            << "), so they are made with " << chosen.description << "\n";
  return chosen.settings;
}

// A noise sd beyond this many times the curve's own travel is a unit mistake
// (a sd in millimetres: 100 m of noise on an 8 cm drop), never data.
constexpr double kMaxNoisePerTravel = 10.0;

// A noise sd above the curve's own travel (5 cm of noise on a 3 cm drop: a
// unit mistake, or data that say little of the model) is written, with a
// word; one beyond kMaxNoisePerTravel travels is refused, nothing written.
void check_noise_against_the_motion(double noise_m, const std::vector<double>& clean) {
  if (clean.empty()) return;
  const auto [lowest, highest] = std::minmax_element(clean.begin(), clean.end());
  const double travel = *highest - *lowest;
  if (!(noise_m > travel)) return;
  if (noise_m > kMaxNoisePerTravel * travel)
    throw CommandLineError({"--noise " + number_text(noise_m) + " m is more than " + number_text(kMaxNoisePerTravel) +
                            " times the curve's own travel (" + number_text(travel) +
                            " m): the data would hold nothing of the model; give the noise sd in metres (a sd in "
                            "millimetres?); nothing was written"});
  std::cerr << "synthesize: warning: --noise " << number_text(noise_m) << " m is larger than the curve's own travel ("
            << number_text(travel) << " m): its data say little about the model; noise in millimetres?\n";
}

// The CSV's header comment: what made the curve, so it is never taken for
// measured data.
std::string provenance_comment(const SynthesizeOptions& o, const std::string& scenario_path, const ModelInputs& in,
                               const IntegratorSettings& integrator, const study::CalibrationChannel& channel,
                               std::uint64_t seed) {
  std::ostringstream comment;
  comment << "SYNTHETIC measured drop curve, NOT experimental data.\n"
          << "Made by `rover synthesize` from " << scenario_path << " at f = " << in.sharpness_f
          << ", c_q = " << in.damping_c_q << ", M0 = [";
  for (int j = 0; j < kNumSJoints; ++j) comment << (j ? ", " : "") << in.preload_Nm[j];
  comment << "],\nGaussian noise sd " << o.noise_m << " m (seed " << seed << "), time offset "
          << o.offset_s << " s (t_data = t_release + offset), " << o.rate_hz << " Hz,\n"
          << "integrator " << integrator_name(integrator.method);
  if (integrator.method == IntegratorMethod::kRungeKutta4)
    comment << " (step " << integrator.fixed_step_s << " s)";
  else if (integrator.method == IntegratorMethod::kDormandPrince45)
    comment << " (rtol " << integrator.relative_tolerance << ", atol " << integrator.absolute_tolerance << ")";
  else
    comment << " (rtol " << integrator.relative_tolerance << ", atol " << integrator.absolute_tolerance
            << ", slip_tol " << integrator.slip_tolerance << ")";
  comment << ".\nColumns: t [s], z [m] = " << channel.name << ", the " << channel.description << ".";
  return comment.str();
}

int run_synthesize(SynthesizeOptions o) {
  FlagChecks checks;
  checks.output_file("--out", o.out);
  checks.non_negative("--noise", o.noise_m);
  checks.finite("--offset", o.offset_s);
  checks.positive("--rate", o.rate_hz);
  const std::uint64_t seed = checks.seed("--seed", o.seed);
  check_overrides(o.overrides, checks);
  try {
    (void)study::calibration_channel(o.channel);
  } catch (const std::invalid_argument& e) {
    checks.add(std::string("--channel: ") + e.what());
  }
  check_integrator_flag(checks, o.integrator);
  checks.throw_if_any();
  const study::CalibrationChannel& channel = study::calibration_channel(o.channel);

  const std::string scenario_path = path_option(o.scenario_option, o.scenario, kDefaultScenario);
  io::ScenarioSetup setup = io::load_scenario(scenario_path);
  io::InputFiles inputs;  // the scenario and the files it names
  inputs.add(scenario_path, "--scenario");
  inputs.add_all(setup.files);
  checks.not_an_input("--out", o.out, inputs, io::WrittenBeside::kTemporaries);  // <out>.partial too
  checks.throw_if_any();
  checks.output_format("--out", o.out, "CSV", ".csv");  // after: an input it would destroy is named first
  checks.throw_if_any();
  // A different method comes with its own default tolerances, as in `rover simulate`.
  if (!o.integrator.empty())
    setup.scenario.integrator = default_integrator_settings(integrator_from_name(o.integrator));
  if (o.offset_option == nullptr || o.offset_option->count() == 0) o.offset_s = default_offset(setup.scenario.duration_s);
  check_data_clock(o, setup.scenario.duration_s, scenario_path);
  setup.scenario.integrator = data_integrator(
      setup.scenario.integrator, o.integrator.empty() ? "the scenario's integrator" : "--integrator", o.noise_m);
  const ModelInputs in = apply_overrides(o.overrides, setup.inputs);
  InterruptibleOutputs outputs({o.out});  // from the run on, a signal ends the command with a word
  HeldOutputs held;  // before the run: a file another process writes is refused at once
  held.hold("--out", o.out);
  const Trajectory tr = simulate_interruptibly(setup.model, setup.scenario, in);
  if (!tr.ok()) {  // a failed run, as simulate's: status 2, nothing written
    std::cerr << "rover synthesize: error: the run failed: " << tr.message << "; nothing was written\n";
    return kFailedRunStatus;
  }
  const std::vector<double> clean = study::channel_values(tr, channel.channel);
  boost::random::mt19937_64 engine(seed);
  boost::random::normal_distribution<double> noise(0.0, o.noise_m);
  // Data clock: t_d = t_sim + offset, from 0 to the end of the run; before the
  // release the rover hangs at its initial height.
  std::vector<double> t, z;
  const std::size_t points = data_point_count(setup.scenario.duration_s, o.offset_s, o.rate_hz);
  for (std::size_t k = 0; k < points; ++k) {
    const double td = static_cast<double>(k) / o.rate_hz;
    t.push_back(td);
    z.push_back(interpolate(tr.t, clean, td - o.offset_s) + (o.noise_m > 0 ? noise(engine) : 0.0));
  }
  // A curve that rover compare and calibrate would refuse is not written.
  check_noise_against_the_motion(o.noise_m, clean);
  for (std::size_t k = 0; k < z.size(); ++k)
    if (!(std::abs(z[k]) < io::kMeasuredCurveMaxAbsHeight_m))
      throw CommandLineError({"--noise " + number_text(o.noise_m) + " m gives a height of " + number_text(z[k]) +
                              " m at t = " + number_text(t[k]) + " s, beyond the |z| < " +
                              number_text(io::kMeasuredCurveMaxAbsHeight_m) +
                              " m that rover compare and calibrate accept; give a noise sd in metres, far below "
                              "that; nothing was written"});
  const std::string comment = provenance_comment(o, scenario_path, in, setup.scenario.integrator, channel, seed);
  if (!io::write_csv(o.out, {"t", "z"}, {t, z}, comment, outputs.stop()))
    outputs.interrupted_while("writing " + o.out);
  std::cerr << "synthesize: wrote " << t.size() << " points of " << channel.name << " to " << o.out << "\n";
  outputs.written(o.out);
  return 0;
}

const RegisterCommand synthesize_command{
    70, "synthesize", "Make a SYNTHETIC measured drop curve (t,z CSV of one channel) with noise and a time offset",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<SynthesizeOptions>();
      app.footer(
          "The paper's measurements are not public; this makes stand-ins with known answers for\n"
          "calibration tests. The file's comment header records every parameter.\n\n"
          "Example (the shipped configs/data/drop_horizontal_synthetic.csv):\n"
          "  rover synthesize --scenario configs/scenarios/drop_horizontal.json --cq 0.25 \\\n"
          "      --noise 1e-4 --offset 0.05 --rate 500 --seed 7 --out configs/data/drop_horizontal_synthetic.csv\n"
          "The right bogie pin of the skewed drop (configs/data/drop_skewed_B_r_z_synthetic.csv):\n"
          "  rover synthesize --scenario configs/scenarios/drop_skewed.json --channel B_r_z --cq 0.25 \\\n"
          "      --noise 1.2e-4 --offset 0.08 --rate 500 --seed 13 --out configs/data/drop_skewed_B_r_z_synthetic.csv");
      o->scenario_option = app.add_option("--scenario", o->scenario, "Scenario file")
                               ->capture_default_str()
                               ->check(CLI::ExistingFile);
      app.add_option("--out", o->out, "CSV file to write")->required();
      std::string channels;
      for (const study::CalibrationChannel& c : study::calibration_channels())
        channels += (channels.empty() ? "" : ", ") + c.name + " (" + c.description + ")";
      app.add_option("--channel", o->channel, "The measured channel [m]: " + channels)->capture_default_str();
      app.add_option("--integrator", o->integrator,
                     "Override the scenario's integrator, with that method's default tolerances: " +
                         integrator_choices_text());
      add_input_overrides(app, o->overrides);
      app.add_option("--noise", o->noise_m, "Measurement noise standard deviation [m]")->capture_default_str();
      o->offset_option = app.add_option("--offset", o->offset_s,
                                        "Time of the release on the data clock [s] (default 0.05, at most half the "
                                        "scenario's duration)");
      app.add_option("--rate", o->rate_hz, "Sample rate of the data [Hz]")->capture_default_str();
      app.add_option("--seed", o->seed, "Noise seed, an integer from 0 to 2^64 - 1")
          ->capture_default_str();
      return [o] { return run_synthesize(*o); };
    }};

}  // namespace
}  // namespace rover::cli
