// See surface.hpp.
#include "study/surface.hpp"

#include <cmath>
#include <iostream>

#include "core/simulate.hpp"
#include "io/hdf5_file.hpp"
#include "io/plot.hpp"
#include "io/trajectory_io.hpp"
#include "study/sampling.hpp"
#include "study/study_runner.hpp"

namespace rover::study {
namespace {

std::vector<double> parse_axis(const io::JsonReader& parent, const std::string& key) {
  const io::JsonReader a = parent.child(key);
  const double min = a.positive("min"), max = a.positive("max");
  const int count = a.integer("count");
  if (count < 1) a.fail("count", "the grid needs at least one point");
  if (!(max >= min)) a.fail("max", "must not be below min (" + std::to_string(min) + ")");
  const std::string spacing = a.string_or("spacing", "linear");
  std::vector<double> v;
  if (spacing == "log") v = log_grid(min, max, count);
  else if (spacing == "linear") v = linear_grid(min, max, count);
  else a.fail("spacing", "must be 'linear' or 'log'");
  a.finish();
  return v;
}

// Values of one run: rms, t_c, right-hand sides, steps.
enum { kRms = 0, kTc = 1, kRhs = 2, kSteps = 3 };

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
  s.common = parse_study_common(r, "surface");
  s.f = parse_axis(r, "f");
  s.c_q = parse_axis(r, "c_q");
  if (r.has("sweep")) {
    const io::JsonReader sw = r.child("sweep");
    s.sweep_f = parse_axis(sw, "f");
    s.sweep_c_q = sw.non_negative("c_q");
    sw.finish();
  }
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
    const double offset = ref.number_or("time_offset", 0.0);
    for (double& t : c.t) t -= offset;
    s.reference_t = c.t;
    s.reference_z = c.y;
    s.reference_description = "file " + file;
  } else {
    const io::JsonReader sim = ref.child("simulate");
    ModelInputs in = io::parse_simulation_inputs(sim, s.common.setup.inputs);
    const Trajectory tr = simulate(s.common.setup.model, s.common.setup.scenario, in);
    if (!tr.ok()) ref.fail("simulate", "the reference run failed: " + tr.message);
    s.reference_t = tr.t;
    s.reference_z = tr.B_l_z;
    s.reference_description = "simulated at f = " + std::to_string(in.sharpness_f) +
                              ", c_q = " + std::to_string(in.damping_c_q);
  }
  ref.finish();
  r.finish();
  return s;
}

std::string run_surface(const SurfaceStudy& study, const StudyRunControl& control) {
  const io::ScenarioSetup& setup = study.common.setup;
  const std::string out = results_path(study.common, control.results_path);
  const int nf = static_cast<int>(study.f.size()), nc = static_cast<int>(study.c_q.size());
  const int grid_tasks = nf * nc, tasks = grid_tasks + static_cast<int>(study.sweep_f.size());
  auto compute = [&](int i) {
    ModelInputs in = setup.inputs;
    if (i < grid_tasks) {
      in.sharpness_f = study.f[static_cast<std::size_t>(i / nc)];
      in.damping_c_q = study.c_q[static_cast<std::size_t>(i % nc)];
    } else {
      in.sharpness_f = study.sweep_f[static_cast<std::size_t>(i - grid_tasks)];
      in.damping_c_q = study.sweep_c_q;
    }
    const Trajectory tr = simulate(setup.model, setup.scenario, in);
    const double rms = tr.ok() ? rms_difference(tr.t, tr.B_l_z, study.reference_t, study.reference_z)
                               : std::nan("");
    return TaskResult{i, static_cast<int>(tr.status), tr.message,
                      {rms, tr.wall_time_s, static_cast<double>(tr.rhs_evaluations),
                       static_cast<double>(tr.steps)}};
  };
  StudyRunOptions options{out, study.common.fingerprint, control.resume, "surface",
                          control.progress_interval_s};
  const std::vector<TaskResult> results = run_study_tasks(tasks, compute, options);
  if (world_rank() != 0) return out;

  const double nan = std::nan("");
  Eigen::MatrixXd rms = Eigen::MatrixXd::Constant(nf, nc, nan), tc = rms, rhs = rms;
  std::vector<int> status(static_cast<std::size_t>(grid_tasks), 0);
  std::vector<double> sweep_tc(study.sweep_f.size(), nan), sweep_rhs(study.sweep_f.size(), nan);
  std::vector<std::string> messages(static_cast<std::size_t>(tasks));
  int failed = 0;
  for (const TaskResult& r : results) {
    messages[static_cast<std::size_t>(r.index)] = r.message;
    failed += r.status != 0;
    if (r.index < grid_tasks) {
      status[static_cast<std::size_t>(r.index)] = r.status;
      rms(r.index / nc, r.index % nc) = r.values[kRms];
      tc(r.index / nc, r.index % nc) = r.values[kTc];
      rhs(r.index / nc, r.index % nc) = r.values[kRhs];
    } else {
      sweep_tc[static_cast<std::size_t>(r.index - grid_tasks)] = r.values[kTc];
      sweep_rhs[static_cast<std::size_t>(r.index - grid_tasks)] = r.values[kRhs];
    }
  }
  const auto regression = linear_regression(study.sweep_f, sweep_tc);
  const auto& integ = setup.scenario.integrator;

  io::Hdf5Writer h5(out);
  h5.write("/f", study.f);
  h5.write("/c_q", study.c_q);
  h5.write("/rms", rms);
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
  write_study_provenance(h5, study.common);
  h5.attribute("/", "scenario", setup.scenario.name);
  h5.attribute("/", "reference", study.reference_description);
  h5.attribute("/", "t_c_meaning", "wall time of one simulate() call on one core, seconds");
  h5.attribute("/", "failed_runs", static_cast<long long>(failed));
  h5.commit();
  remove_checkpoint(out);
  std::cerr << "surface: " << tasks << " runs (" << failed << " failed), wrote " << out << "\n";

  if (control.plot) {
    const std::string stem = out.substr(0, out.size() - 3);
    auto surface_png = [&](const Eigen::MatrixXd& z, double scale, const std::string& label,
                           const std::string& suffix) {
      io::SurfacePlot p;
      p.title = study.common.name + ": " + label + " (" + integrator_name(integ.method) + ")";
      p.x_label = "f [1/rad]";
      p.y_label = "c_q [N m s/rad]";
      p.z_label = label;
      p.x = study.f;
      p.y = study.c_q;
      p.log_x = true;
      for (int j = 0; j < nc; ++j)
        for (int i = 0; i < nf; ++i) p.z.push_back(scale * z(i, j));
      io::write_png(p, stem + suffix);
      std::cerr << "surface: wrote " << stem + suffix << "\n";
    };
    try {
      if (nf > 1 && nc > 1) {
        surface_png(rms, 1000.0, "RMS of B_l z [mm]", "_rms.png");
        surface_png(tc, 1.0, "t_c [s]", "_tc.png");
      }
      if (study.sweep_f.size() > 1) {
        io::LinePlot p;
        p.title = study.common.name + ": t_c over f (" + integrator_name(integ.method) + ")";
        p.x_label = "f [1/rad]";
        p.y_label = "t_c [s]";
        io::Series pts;
        pts.label = "runs";
        pts.x = study.sweep_f;
        pts.y = sweep_tc;
        pts.style = io::SeriesStyle::points;
        io::Series fit;
        fit.label = "t_c = a + b f (r^2 = " + std::to_string(regression[2]).substr(0, 5) + ")";
        for (double f : study.sweep_f) {
          fit.x.push_back(f);
          fit.y.push_back(regression[0] + regression[1] * f);
        }
        p.series = {pts, fit};
        io::write_png(p, stem + "_sweep.png");
        std::cerr << "surface: wrote " << stem + "_sweep.png" << "\n";
      }
    } catch (const std::exception& e) {
      std::cerr << "surface: warning: no plot (" << e.what() << ")\n";
    }
  }
  return out;
}

}  // namespace rover::study
