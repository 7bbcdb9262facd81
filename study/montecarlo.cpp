// See montecarlo.hpp.
#include "study/montecarlo.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>

#include "core/metrics.hpp"
#include "core/simulate.hpp"
#include "io/hdf5_file.hpp"
#include "io/plot.hpp"
#include "study/band_statistics.hpp"
#include "study/sampling.hpp"
#include "study/study_runner.hpp"

namespace rover::study {
namespace {

// Layout of one sample's values.
constexpr int kZMin = 0, kZRest = 1, kWall = 2, kCurve = 3;

std::vector<double> to_mm(const std::vector<double>& v) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [](double x) { return 1000.0 * x; });
  return out;
}

}  // namespace

MonteCarloStudy load_montecarlo_study(const std::string& path) {
  const io::Json json = io::read_json_file(path);
  const io::JsonReader r(json, path);
  MonteCarloStudy s;
  s.common = parse_study_common(r, "montecarlo");
  s.samples = r.integer("samples");
  if (s.samples <= 0) r.fail("samples", "must be a positive number of samples");
  const double seed = r.number("seed");
  if (seed < 0 || seed != std::floor(seed)) r.fail("seed", "must be a non-negative integer");
  s.seed = static_cast<std::uint64_t>(seed);
  s.sd_scale = r.has("sd_scale") ? r.non_negative("sd_scale") : 1.0;
  s.rest_time_s = r.has("rest_time") ? r.positive("rest_time") : s.common.setup.scenario.duration_s;
  if (s.rest_time_s > s.common.setup.scenario.duration_s + 1e-12)
    r.fail("rest_time", "is after the end of the scenario (" +
                            std::to_string(s.common.setup.scenario.duration_s) + " s)");
  r.finish();
  return s;
}

std::string run_montecarlo(const MonteCarloStudy& study, const StudyRunControl& control) {
  const io::ScenarioSetup& setup = study.common.setup;
  const std::string out = results_path(study.common, control.results_path);
  const auto draw = [&](int i) {
    return sample_preloads(setup.model.parameters.s_structure, study.seed,
                           static_cast<std::uint64_t>(i), study.sd_scale);
  };
  auto compute = [&](int i) {
    ModelInputs inputs = setup.inputs;
    inputs.preload_Nm = draw(i);
    const Trajectory tr = simulate(setup.model, setup.scenario, inputs);
    TaskResult r{i, static_cast<int>(tr.status), tr.message, {}};
    const double nan = std::nan("");
    r.values = {nan, nan, tr.wall_time_s};
    if (tr.ok()) {
      r.values[kZMin] = *std::min_element(tr.B_l_z.begin(), tr.B_l_z.end());
      r.values[kZRest] = interpolate(tr.t, tr.B_l_z, study.rest_time_s);
    }
    r.values.insert(r.values.end(), tr.B_l_z.begin(), tr.B_l_z.end());
    return r;
  };
  StudyRunOptions options{out, study.common.fingerprint, control.resume, "montecarlo",
                          control.progress_interval_s};
  const std::vector<TaskResult> results = run_study_tasks(study.samples, compute, options);
  if (world_rank() != 0) return out;

  // Assemble: every curve on the scenario's output grid, NaN where a run stopped early.
  const Scenario& sc = setup.scenario;
  const double period = 1.0 / sc.output_rate_hz;
  const auto T = static_cast<Eigen::Index>(output_sample_count(sc));
  std::vector<double> t(static_cast<std::size_t>(T));
  for (Eigen::Index k = 0; k < T; ++k) t[static_cast<std::size_t>(k)] = static_cast<double>(k) * period;
  const auto N = static_cast<Eigen::Index>(study.samples);
  Eigen::MatrixXd curves = Eigen::MatrixXd::Constant(N, T, std::nan(""));
  Eigen::MatrixXd m0(N, kNumSJoints);
  std::vector<double> deflection(results.size()), at_rest(results.size()), wall(results.size());
  std::vector<int> status(results.size());
  std::vector<std::string> messages(results.size());
  int failed = 0;
  for (const TaskResult& r : results) {
    const auto i = static_cast<std::size_t>(r.index);
    const auto draws = draw(r.index);
    for (int j = 0; j < kNumSJoints; ++j) m0(r.index, j) = draws[j];
    status[i] = r.status;
    messages[i] = r.message;
    failed += r.status != 0;
    if (r.values.size() < kCurve) continue;
    deflection[i] = r.values[kZRest] - r.values[kZMin];
    at_rest[i] = r.values[kZRest];
    wall[i] = r.values[kWall];
    const auto n = std::min<Eigen::Index>(T, static_cast<Eigen::Index>(r.values.size()) - kCurve);
    if (r.status == 0)
      for (Eigen::Index k = 0; k < n; ++k) curves(r.index, k) = r.values[kCurve + static_cast<std::size_t>(k)];
  }
  const Band band = band_statistics(curves);

  io::Hdf5Writer h5(out);
  h5.write("/t", t);
  h5.write("/samples/M0", m0);
  h5.write("/curves/B_l_z", curves);
  h5.write("/band/mean", band.mean);
  h5.write("/band/std", band.std);
  h5.write("/band/lower", band.lower);
  h5.write("/band/upper", band.upper);
  h5.write("/band/p00135", band.p00135);
  h5.write("/band/p99865", band.p99865);
  h5.write("/samples/deflection", deflection);
  h5.write("/samples/at_rest", at_rest);
  h5.write("/samples/status", status);
  h5.write("/samples/message", messages);
  h5.write("/samples/wall_time_s", wall);
  write_study_provenance(h5, study.common);
  h5.attribute("/", "scenario", sc.name);
  h5.attribute("/", "scenario_file", setup.scenario_path);
  h5.attribute("/", "samples", static_cast<long long>(study.samples));
  h5.attribute("/", "samples_used_in_band", static_cast<long long>(band.samples_used));
  h5.attribute("/", "failed_samples", static_cast<long long>(failed));
  h5.attribute("/", "seed", static_cast<long long>(study.seed));
  h5.attribute("/", "sd_scale", study.sd_scale);
  h5.attribute("/", "rest_time_s", study.rest_time_s);
  h5.attribute("/", "f", setup.inputs.sharpness_f);
  h5.attribute("/", "c_q", setup.inputs.damping_c_q);
  const auto& mean = setup.model.parameters.s_structure.preload_mean_Nm;
  const auto& sd = setup.model.parameters.s_structure.preload_sd_Nm;
  h5.attribute("/", "M0_mean", std::vector<double>(mean.begin(), mean.end()));
  h5.attribute("/", "M0_sd", std::vector<double>(sd.begin(), sd.end()));
  h5.commit();
  remove_checkpoint(out);
  std::cerr << "montecarlo: " << study.samples << " samples (" << failed << " failed), wrote " << out << "\n";

  if (control.plot) {
    const std::string png = out.substr(0, out.size() - 3) + ".png";
    io::LinePlot plot;
    plot.title = study.common.name + ": B_l z, " + std::to_string(band.samples_used) + " samples";
    plot.x_label = "t [s]";
    plot.y_label = "B_l z [mm]";
    io::Band sigma;
    sigma.label = "mean -+ 3 sd";
    sigma.x = t;
    sigma.lower = to_mm(band.lower);
    sigma.upper = to_mm(band.upper);
    plot.bands.push_back(sigma);
    io::Series m;
    m.label = "mean";
    m.x = t;
    m.y = to_mm(band.mean);
    plot.series.push_back(m);
    for (const auto& [label, values] : {std::pair{"0.135 % quantile", &band.p00135},
                                        std::pair{"99.865 % quantile", &band.p99865}}) {
      io::Series q;
      q.label = label;
      q.x = t;
      q.y = to_mm(*values);
      q.style = io::SeriesStyle::dashed;
      plot.series.push_back(q);
    }
    io::write_png_or_warn(plot, png, "montecarlo", std::cerr);
  }
  return out;
}

}  // namespace rover::study
