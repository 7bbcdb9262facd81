// See surface.hpp.
#include "study/studies/surface.hpp"

#include <cmath>
#include <iostream>

#include "core/number_text.hpp"
#include "core/simulate.hpp"
#include "study/studies/study_output.hpp"
#include "io/hdf5_file.hpp"
#include "io/plot.hpp"
#include "io/trajectory_io.hpp"
#include "study/design/sampling.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::study {
namespace {

std::vector<double> parse_axis(const io::JsonReader& parent, const std::string& key) {
  const io::JsonReader a = parent.child(key);
  const double min = a.positive("min"), max = a.positive("max");
  const int count = a.integer("count");
  if (count < 1) a.fail("count", "the grid needs at least one point");
  if (count > 1'000'000) a.fail("count", "more than 1e6 points on one axis");
  if (!(max >= min)) a.fail("max", "must not be below min (" + std::to_string(min) + ")");
  const std::string spacing = a.string_or("spacing", "linear");
  std::vector<double> v;
  if (spacing == "log") v = log_grid(min, max, count);
  else if (spacing == "linear") v = linear_grid(min, max, count);
  else a.fail("spacing", "must be 'linear' or 'log'");
  a.finish();
  return v;
}


}  // namespace

std::array<double, 3> linear_regression(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  if (x.size() < 2 || x.size() != y.size()) return {std::nan(""), std::nan(""), std::nan("")};
  double sx = 0, sy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
  }
  const double mx = sx / n, my = sy / n;
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  const double b = sxy / sxx, a = my - b * mx;
  const double r2 = syy > 0 ? (sxy * sxy) / (sxx * syy) : 1.0;
  return {a, b, r2};
}

SurfaceStudy load_surface_study(const std::string& path) {
  const io::Json json = io::read_json_file(path);
  const io::JsonReader r(json, path);
  SurfaceStudy s;
  s.path = path;
  if (r.string("type") != "surface") r.fail("type", "this command runs 'surface' studies");
  s.name = r.string("name");
  if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos || s.name == "." || s.name == "..")
    r.fail("name", "must be a plain file name (results go to results/<name>.h5)");
  r.string_or("description", "");
  const std::string scenario = io::resolve_relative(path, r.string("scenario"));
  IntegratorSettings scenario_integrator;
  io::ScenarioSetup nominal;
  try {
    s.sources = io::read_scenario_sources(scenario);
    nominal = io::build_scenario(s.sources);
  } catch (const io::ConfigError& e) {
    r.fail("scenario", e.what());
  }
  if (r.has("integrator"))
    s.integrator = io::parse_integrator_settings(r.child("integrator"), nominal.scenario.integrator);
  s.f = parse_axis(r, "f");
  s.c_q = parse_axis(r, "c_q");
  if (static_cast<double>(s.f.size()) * static_cast<double>(s.c_q.size()) > 1e6)
    r.fail("f", "the grid would have more than 1e6 points");
  if (r.has("sweep")) {
    const io::JsonReader sw = r.child("sweep");
    s.sweep_f = parse_axis(sw, "f");
    s.sweep_c_q = sw.non_negative("c_q");
    sw.finish();
  }
  std::string reference_text;
  const io::JsonReader ref = r.child("reference");
  if (ref.has("file") == ref.has("simulate"))
    ref.fail("file", "give exactly one of 'file' (a measured or simulated curve) and 'simulate'");
  if (ref.has("file")) {
    const std::string file = io::resolve_relative(path, ref.string("file"));
    io::Curve c;
    try {
      c = io::read_curve(file, "B_l_z");
    } catch (const std::exception& e) {
      ref.fail("file", e.what());
    }
    if (c.t.size() < 3) ref.fail("file", file + ": a reference curve needs at least 3 samples, got " + std::to_string(c.t.size()));
    for (std::size_t i = 1; i < c.t.size(); ++i)
      if (!(c.t[i] > c.t[i - 1]))
        ref.fail("file", file + ": times must increase strictly (sample " + std::to_string(i + 1) + ": " +
                             std::to_string(c.t[i]) + " after " + std::to_string(c.t[i - 1]) + ")");
    for (double z : c.y)
      if (!std::isfinite(z) || std::abs(z) > 1e3) ref.fail("file", file + ": values must be finite heights in metres");
    const double offset = ref.number_or("time_offset", 0.0);
    for (double& t : c.t) t -= offset;
    s.reference_t = c.t;
    s.reference_z = c.y;
    s.reference_description = "file " + file;
    reference_text = file_text(file) + "|offset " + std::to_string(offset);
  } else {
    const io::JsonReader sim = ref.child("simulate");
    const ModelInputs in = io::parse_simulation_inputs(sim, nominal.inputs);
    s.simulate_reference = true;
    s.reference_f = in.sharpness_f;
    s.reference_c_q = in.damping_c_q;
    s.reference_description = "simulated at f = " + std::to_string(in.sharpness_f) +
                              ", c_q = " + std::to_string(in.damping_c_q);
    reference_text = s.reference_description;
  }
  ref.finish();
  r.finish();
  s.fingerprint = io::config_fingerprint(file_text(path) + file_text(scenario) + file_text(s.sources.rover_path) +
                                         file_text(s.sources.terrain_path) + reference_text);
  return s;
}

std::string run_surface(const SurfaceStudy& study, const StudyRunControl& control) {
  const std::string out = checked_results_path(study.name, control.results_path);
  const std::vector<std::string> inputs{"s_structure.f", "s_structure.c_q"};
  auto reference = std::make_shared<ReferenceCurve>();
  reference->path = study.reference_description;
  if (study.simulate_reference) {
    const RoverStudyModel reference_model(study.sources, inputs, {}, {Channel::kBlz}, study.integrator);
    const double point[2] = {study.reference_f, study.reference_c_q};
    RunRecord failure;
    const std::optional<Trajectory> tr = reference_model.simulate_at(point, &failure);
    if (!tr || !tr->ok())
      throw std::runtime_error(study.path + ": field 'reference.simulate': the reference run failed: " +
                               (tr ? tr->message : failure.message));
    reference->t = tr->t;
    reference->value = tr->B_l_z;
  } else {
    reference->t = study.reference_t;
    reference->value = study.reference_z;
  }
  QoiSpec rms;
  rms.name = "rms";
  rms.kind = QoiKind::kRmsVs;
  rms.reference = reference;
  const RoverStudyModel model(study.sources, inputs, {rms}, {}, study.integrator);
  const IntegratorSettings& integ = model.nominal().scenario.integrator;

  const int nf = static_cast<int>(study.f.size()), nc = static_cast<int>(study.c_q.size());
  const int grid_tasks = nf * nc, tasks = grid_tasks + static_cast<int>(study.sweep_f.size());
  DesignMatrix x(tasks, 2);
  for (int i = 0; i < grid_tasks; ++i) x.row(i) << study.f[static_cast<std::size_t>(i / nc)], study.c_q[static_cast<std::size_t>(i % nc)];
  for (int i = grid_tasks; i < tasks; ++i) x.row(i) << study.sweep_f[static_cast<std::size_t>(i - grid_tasks)], study.sweep_c_q;

  const double nan = std::nan("");
  Eigen::MatrixXd rms_grid = Eigen::MatrixXd::Constant(nf, nc, nan), tc = rms_grid, rhs = rms_grid;
  std::vector<int> status(static_cast<std::size_t>(grid_tasks), 0);
  std::vector<std::string> messages(static_cast<std::size_t>(grid_tasks));
  std::vector<double> sweep_tc(study.sweep_f.size(), nan), sweep_rhs(study.sweep_f.size(), nan);
  int failed = 0;
  const RecordLayout layout = model.layout();
  auto compute = [&](int i) { return encode_record(i, model.run(x.row(i).data())); };
  auto consume = [&](TaskResult&& task) {
    const int i = task.index;
    const RunRecord r = decode_record(layout, std::move(task));
    failed += r.ok() ? 0 : 1;
    if (i < grid_tasks) {
      status[static_cast<std::size_t>(i)] = r.status;
      messages[static_cast<std::size_t>(i)] = r.message;
      if (!r.ok()) return;
      rms_grid(i / nc, i % nc) = r.qoi[0];
      tc(i / nc, i % nc) = r.wall_time_s;
      rhs(i / nc, i % nc) = r.rhs_evaluations;
    } else if (r.ok()) {
      sweep_tc[static_cast<std::size_t>(i - grid_tasks)] = r.wall_time_s;
      sweep_rhs[static_cast<std::size_t>(i - grid_tasks)] = r.rhs_evaluations;
    }
  };
  StudyRunOptions options{out, study.fingerprint, control.resume, "surface", control.progress_interval_s,
                          control.resume_command, control.checkpoint};
  stream_study_tasks(tasks, compute, consume, options);
  if (world_rank() != 0) return out;

  std::vector<double> fit_f, fit_tc;
  for (std::size_t k = 0; k < study.sweep_f.size(); ++k)
    if (std::isfinite(sweep_tc[k])) {
      fit_f.push_back(study.sweep_f[k]);
      fit_tc.push_back(sweep_tc[k]);
    }
  const std::array<double, 3> regression = linear_regression(fit_f, fit_tc);

  io::Hdf5Writer h5(out);
  h5.write("/f", study.f);
  h5.write("/c_q", study.c_q);
  h5.write("/rms", rms_grid);
  h5.write("/t_c", tc);
  h5.write("/rhs_evaluations", rhs);
  h5.write("/status", std::vector<double>(status.begin(), status.end()),
           static_cast<std::size_t>(nf), static_cast<std::size_t>(nc));
  h5.write("/messages", messages);
  h5.write("/reference/t", study.reference_t);
  h5.write("/reference/z", study.reference_z);
  if (!study.sweep_f.empty()) {
    h5.write("/sweep/f", study.sweep_f);
    h5.write("/sweep/t_c", sweep_tc);
    h5.write("/sweep/rhs_evaluations", sweep_rhs);
    h5.write("/sweep/regression", std::vector<double>(regression.begin(), regression.end()));
    h5.attribute("/sweep", "c_q", study.sweep_c_q);
    h5.attribute("/sweep/regression", "meaning", "t_c = a + b f: [a (s), b (s), r^2]");
  }
  write_base_provenance(h5, "surface", study.name, study.path, &integ, study.fingerprint);
  h5.attribute("/", "scenario", model.nominal().scenario.name);
  h5.attribute("/", "reference", study.reference_description);
  h5.attribute("/", "t_c_meaning", "wall time of one simulate() call on one core, seconds");
  h5.attribute("/", "failed_runs", static_cast<long long>(failed));
  h5.commit();
  remove_checkpoint(out);
  std::cerr << "surface: " << tasks << " runs (" << failed << " failed), wrote " << out << "\n";

  if (control.plot) {
    const auto png = [&](const std::string& suffix) { return sibling_path(out, suffix); };
    auto surface_png = [&](const Eigen::MatrixXd& z, double scale, const std::string& label,
                           const std::string& suffix) {
      io::SurfacePlot p;
      p.title = study.name + ": " + label + " (" + integrator_name(integ.method) + ")";
      p.x_label = "f [1/rad]";
      p.y_label = "c_q [N m s/rad]";
      p.z_label = label;
      p.x = study.f;
      p.y = study.c_q;
      p.log_x = true;
      for (int j = 0; j < nc; ++j)
        for (int i = 0; i < nf; ++i) p.z.push_back(scale * z(i, j));
      io::write_png(p, png(suffix));
      std::cerr << "surface: wrote " << png(suffix) << "\n";
    };
    try {
      if (nf > 1 && nc > 1) {
        surface_png(rms_grid, 1000.0, "RMS of B_l z [mm]", "_rms.png");
        surface_png(tc, 1.0, "t_c [s]", "_tc.png");
      }
      if (study.sweep_f.size() > 1) {
        io::LinePlot p;
        p.title = study.name + ": t_c over f (" + integrator_name(integ.method) + ")";
        p.x_label = "f [1/rad]";
        p.y_label = "t_c [s]";
        io::Series pts;
        pts.label = "runs";
        pts.x = study.sweep_f;
        pts.y = sweep_tc;
        pts.style = io::SeriesStyle::points;
        io::Series fit;
        fit.label = "t_c = a + b f (r^2 = " + number_text(regression[2]) + ")";
        for (double f : study.sweep_f) {
          fit.x.push_back(f);
          fit.y.push_back(regression[0] + regression[1] * f);
        }
        p.series = {pts, fit};
        io::write_png(p, png("_sweep.png"));
        std::cerr << "surface: wrote " << png("_sweep.png") << "\n";
      }
    } catch (const std::exception& e) {
      std::cerr << "surface: warning: no plot (" << e.what() << ")\n";
    }
  }
  return out;
}

}  // namespace rover::study
