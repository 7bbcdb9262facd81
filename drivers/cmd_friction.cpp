// `rover friction`: the Makkar friction curve (paper eq. 8) for a set of
// engineering parameters, with its fit quality against the STEP target of
// docs/model.md §6 ("Friction synthesis"), as JSON on stdout and optionally
// as a PNG of mu(v) and the target. Parameters for which no gammas can be
// synthesised (v_k not above v_s, a ratio mu_k / mu_s beyond doubles) are an
// error naming the four values, not the optimiser's message alone.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "core/friction_synthesis.hpp"
#include "core/model_scale.hpp"
#include "drivers/command_registry.hpp"
#include "drivers/held_outputs.hpp"
#include "drivers/interruptible_outputs.hpp"
#include "drivers/options.hpp"
#include "io/json_reader.hpp"
#include "io/plot.hpp"
#include "io/rover_config.hpp"

namespace rover::cli {
namespace {

// The exit status of a result not to be trusted (drivers/main.cpp).
constexpr int kUntrustedResultStatus = 2;

struct FrictionOptions {
  std::string config = kDefaultRoverConfig;
  std::optional<double> mu_static, v_static_mps, mu_kinetic, v_kinetic_mps;  // empty: the config's
  bool synthesize = false;
  std::string png;
  CLI::Option* config_option = nullptr;
};

void write_friction_png(const FrictionParameters& p, const MakkarGammas& gammas,
                        const FrictionFitQuality& quality, const std::string& png_path) {
  constexpr int kSamples = 1001;
  const double v_max_mps = 10.0 * p.v_kinetic_mps;
  io::Series fit{"Makkar fit (eq. 8)", {}, {}, io::SeriesStyle::lines, "#1f77b4", 2.0};
  io::Series target{"STEP target", {}, {}, io::SeriesStyle::dashed, "black", 1.5};
  for (int i = 0; i < kSamples; ++i) {
    const double v = v_max_mps * i / (kSamples - 1);
    fit.x.push_back(1e3 * v);
    fit.y.push_back(makkar_mu(v, gammas));
    target.x.push_back(1e3 * v);
    target.y.push_back(friction_target_mu(v, p));
  }
  io::Series peak{"peak", {1e3 * quality.peak_speed_mps}, {quality.peak_mu},
                  io::SeriesStyle::points, "#d62728", 1.5};
  char title[200];
  std::snprintf(title, sizeof title,
                "Makkar friction: mu_s %.3g at v_s %.3g mm/s, mu_k %.3g at v_k %.3g mm/s "
                "(RMS %.2g, peak %.4g at %.3g mm/s)",
                p.mu_static, 1e3 * p.v_static_mps, p.mu_kinetic, 1e3 * p.v_kinetic_mps,
                quality.rms, quality.peak_mu, 1e3 * quality.peak_speed_mps);
  io::LinePlot plot;
  plot.title = title;
  plot.x_label = "slip speed v [mm/s]";
  plot.y_label = "friction coefficient mu [-]";
  plot.series = {target, fit, peak};
  plot.x_range = io::AxisRange{0.0, 1e3 * v_max_mps};
  const auto parent = std::filesystem::path(png_path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  io::write_png(plot, png_path);
}

// "--mu-s 0.3, --v-s 0.00055, --mu-k 0.2, --v-k 0.002", for messages.
std::string friction_values_text(const FrictionParameters& p) {
  return "--mu-s " + number_text(p.mu_static) + ", --v-s " + number_text(p.v_static_mps) + ", --mu-k " +
         number_text(p.mu_kinetic) + ", --v-k " + number_text(p.v_kinetic_mps);
}

// Checks every flag before the rover file is read: the ranges and scales of
// rover.json's friction section, and the plot's path.
void check_friction_flags(const FrictionOptions& o) {
  FlagChecks checks;
  if (o.mu_static) checks.non_negative("--mu-s", *o.mu_static);
  if (o.v_static_mps) checks.positive("--v-s", *o.v_static_mps);
  if (o.mu_kinetic) checks.non_negative("--mu-k", *o.mu_kinetic);
  if (o.v_kinetic_mps) checks.positive("--v-k", *o.v_kinetic_mps);
  // And their scale (core/model_scale.hpp): beyond it, a unit mistake.
  auto within = [&](const char* flag, const std::optional<double>& value, double bound, const char* unit,
                    const std::string& why) {
    if (!value || !std::isfinite(*value)) return;
    if (const std::string problem = beyond_scale(*value, bound, unit, why); !problem.empty())
      checks.add(std::string(flag) + " " + problem);
  };
  within("--mu-s", o.mu_static, kMaxFrictionCoefficient, "", kFrictionScaleReason);
  within("--v-s", o.v_static_mps, kMaxStribeckSpeed_mps, "m/s", kStribeckScaleReason);
  within("--mu-k", o.mu_kinetic, kMaxFrictionCoefficient, "", kFrictionScaleReason);
  within("--v-k", o.v_kinetic_mps, kMaxStribeckSpeed_mps, "m/s", kStribeckScaleReason);
  for (const auto& [flag, value] : {std::pair{"--v-s", o.v_static_mps}, std::pair{"--v-k", o.v_kinetic_mps}})
    if (value && *value > 0.0)
      if (const std::string problem = below_scale(*value, kMinStribeckSpeed_mps, "m/s", kStribeckBelowScaleReason);
          !problem.empty())
        checks.add(std::string(flag) + " " + problem);
  checks.output_file("--png", o.png, /*regular_only=*/true);
  checks.output_format("--png", o.png, "PNG", ".png");
  checks.distinct_files("--png", o.png, "--config", o.config);
  if (!o.png.empty()) checks.plotter("--png", "give no --png");
  checks.throw_if_any();
}

int run_friction(const FrictionOptions& o) {
  check_friction_flags(o);
  const std::string config = path_option(o.config_option, o.config, kDefaultRoverConfig);
  FrictionParameters p = io::load_rover_parameters(config).friction;
  if (o.mu_static) p.mu_static = *o.mu_static;
  if (o.v_static_mps) p.v_static_mps = *o.v_static_mps;
  if (o.mu_kinetic) p.mu_kinetic = *o.mu_kinetic;
  if (o.v_kinetic_mps) p.v_kinetic_mps = *o.v_kinetic_mps;

  if (!(p.v_kinetic_mps > p.v_static_mps))
    throw CommandLineError({"v_k (" + number_text(p.v_kinetic_mps) + " m/s) must be above v_s (" +
                            number_text(p.v_static_mps) + " m/s): give --v-k above --v-s (those not given are " +
                            config + "'s)"});
  const auto start = std::chrono::steady_clock::now();
  MakkarGammas gammas;
  try {
    gammas = o.synthesize ? synthesize_friction(p) : friction_gammas_for(p);
  } catch (const std::exception& e) {
    throw CommandLineError({"no Makkar gammas for " + friction_values_text(p) + " (the synthesis failed: " +
                            e.what() + ")"});
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool from_config = !o.synthesize && gammas == p.gammas;
  const FrictionFitQuality quality = friction_fit_quality(gammas, p);

  io::Json out;
  out["engineering"] = {{"mu_s", p.mu_static},
                        {"v_s_mps", p.v_static_mps},
                        {"mu_k", p.mu_kinetic},
                        {"v_k_mps", p.v_kinetic_mps}};
  out["gammas"] = gammas;
  out["source"] = from_config ? "config" : "synthesized";
  out["quality"] = {{"rms", quality.rms},
                    {"peak_mu", quality.peak_mu},
                    {"peak_speed_mps", quality.peak_speed_mps},
                    {"acceptable", quality.acceptable}};
  if (!o.png.empty()) out["png"] = o.png;
  try {  // a fit error that overflows (no coefficient within the checked scale is known to)
    require_finite_output(out);
  } catch (const std::runtime_error& e) {
    throw CommandLineError({"no usable Makkar gammas for " + friction_values_text(p) + ": " + e.what() +
                            "; friction coefficients are of order 1"});
  }
  InterruptibleOutputs outputs({o.png});  // a signal while the plot is drawn ends the command with a word
  HeldOutputs held;  // no other process writes the plot while this one does
  held.hold("--png", o.png);
  std::cout << out.dump(2) << "\n";
  if (!from_config) std::cerr << "synthesized the gammas in " << seconds << " s\n";
  if (!quality.acceptable)
    std::cerr << "WARNING: the fit misses the quality bar (RMS < " << kFrictionMaxRms << ", peak within "
              << 100 * kFrictionMaxPeakError << " % of mu_s): these gammas are not to be trusted (exit status 2)"
              << (p.mu_kinetic > p.mu_static ? "; mu_k is above mu_s, where the Makkar law has its peak at mu_s "
                                               "(did you swap --mu-s and --mu-k?)"
                                             : "")
              << "\n";

  if (!o.png.empty()) {
    try {
      outputs.stop_if_signalled();
      write_friction_png(p, gammas, quality, o.png);
      outputs.written(o.png);
    } catch (const study::StudyInterrupted&) {
      throw;
    } catch (const std::exception& e) {  // the numbers above stand without the plot
      outputs.stop_if_signalled();  // gnuplot ended by the same Ctrl-C: said as the interrupt it is
      std::cerr << "warning: no plot: " << e.what() << "\n";
    }
  }
  return quality.acceptable ? 0 : kUntrustedResultStatus;
}

const RegisterCommand friction_command{
    20, "friction",
    "Makkar friction gammas for mu_s, v_s, mu_k, v_k: fit quality as JSON, mu(v) as PNG",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<FrictionOptions>();
      app.footer(
          "Takes the friction section of the rover config, overrides any of mu_s, v_s, mu_k, "
          "v_k given on the command line, and resolves the six gammas of eq. 8 as the model "
          "does: the configured gammas if they still fit (RMS < 0.01 against the STEP target of "
          "docs/model.md §6 on v in [0, 10 v_k], peak within 5 % of mu_s), otherwise a fresh "
          "least-squares synthesis (global NLopt search + local polish, deterministic, ~0.1 s). "
          "--synthesize always fits anew.\n"
          "Output (stdout): {\"engineering\": {mu_s, v_s_mps, mu_k, v_k_mps}, \"gammas\": [6], "
          "\"source\": \"config\"|\"synthesized\", \"quality\": {rms, peak_mu, peak_speed_mps, "
          "acceptable}}. Paste the gammas into the config's friction.gammas to pin them.\n\n"
          "Examples:\n"
          "  rover friction --png results/friction.png\n"
          "  rover friction --mu-s 0.5 --v-s 1e-3 --mu-k 0.35 --v-k 4e-3 --png results/f.png");
      o->config_option = app.add_option("--config", o->config, "Rover parameters (JSON)")
                             ->capture_default_str()
                             ->check(CLI::ExistingFile);
      app.add_option("--mu-s", o->mu_static, "Static friction coefficient mu_s [-] (>= 0)");
      app.add_option("--v-s", o->v_static_mps, "Stiction transition speed v_s [m/s] (> 0)");
      app.add_option("--mu-k", o->mu_kinetic, "Kinetic friction coefficient mu_k [-] (>= 0)");
      app.add_option("--v-k", o->v_kinetic_mps, "Kinetic transition speed v_k [m/s] (> v_s)");
      app.add_flag("--synthesize", o->synthesize,
                   "Fit the gammas even if the configured ones pass the quality bar");
      app.add_option("--png", o->png, "Write mu(v) and the target to this PNG");
      return [o] { return run_friction(*o); };
    }};

}  // namespace
}  // namespace rover::cli
