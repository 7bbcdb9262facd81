// See calibration.hpp.
#include "study/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_real_distribution.hpp>
#include <nlopt.hpp>

#include "core/metrics.hpp"
#include "core/simulate.hpp"
#include "io/csv.hpp"
#include "io/hdf5_file.hpp"
#include "io/plot.hpp"
#include "study/study_runner.hpp"

namespace rover::study {
namespace {

const std::vector<std::string> kFittable{"c_q", "f", "M0_scale", "time_offset"};

// Simulation inputs for parameter values in natural units.
ModelInputs inputs_for(const CalibrationStudy& s, const std::vector<double>& values) {
  ModelInputs in = s.common.setup.inputs;
  for (std::size_t k = 0; k < s.fit.size(); ++k) {
    const std::string& name = s.fit[k].name;
    if (name == "c_q") in.damping_c_q = values[k];
    if (name == "f") in.sharpness_f = values[k];
    if (name == "M0_scale")
      for (auto& m : in.preload_Nm) m *= values[k];
  }
  return in;
}

struct Evaluation {
  double offset = 0.0, rms = 0.0;
  int status = 0;
};

Evaluation evaluate(const CalibrationStudy& s, const std::vector<double>& values) {
  const Trajectory tr = simulate(s.common.setup.model, s.common.setup.scenario, inputs_for(s, values));
  Evaluation e;
  e.status = static_cast<int>(tr.status);
  if (!tr.ok() || tr.t.size() < 2) {
    e.rms = 1.0;  // a failed run is a very bad fit, not the end of the calibration
    return e;
  }
  e.offset = s.offset_initial_s;
  for (std::size_t k = 0; k < s.fit.size(); ++k)
    if (s.fit[k].name == "time_offset") e.offset = values[k];
  const bool offset_fitted = std::any_of(s.fit.begin(), s.fit.end(),
                                         [](const FitParameter& p) { return p.name == "time_offset"; });
  if (!offset_fitted) e.offset = best_offset(tr.t, tr.B_l_z, s.data_t, s.data_z, s.offset_min_s, s.offset_max_s);
  e.rms = shifted_rms(tr.t, tr.B_l_z, s.data_t, s.data_z, e.offset);
  return e;
}

// Internal coordinates: log10 for log-scale parameters.
double to_internal(const FitParameter& p, double v) { return p.log_scale ? std::log10(v) : v; }
double to_natural(const FitParameter& p, double x) { return p.log_scale ? std::pow(10.0, x) : x; }

}  // namespace

double shifted_rms(const std::vector<double>& t, const std::vector<double>& z,
                   const std::vector<double>& t_d, const std::vector<double>& z_d, double offset) {
  double sum = 0.0;
  for (std::size_t i = 0; i < t_d.size(); ++i) {
    const double d = interpolate(t, z, t_d[i] - offset) - z_d[i];
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(t_d.size()));
}

double best_offset(const std::vector<double>& t, const std::vector<double>& z,
                   const std::vector<double>& t_d, const std::vector<double>& z_d, double lo,
                   double hi) {
  const int n = std::max(2, static_cast<int>(std::ceil((hi - lo) / 1e-3)));
  double best = lo, best_rms = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i) {
    const double o = lo + (hi - lo) * i / n;
    const double r = shifted_rms(t, z, t_d, z_d, o);
    if (r < best_rms) {
      best_rms = r;
      best = o;
    }
  }
  // Golden-section polish within one scan step either side.
  double a = std::max(lo, best - (hi - lo) / n), b = std::min(hi, best + (hi - lo) / n);
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = shifted_rms(t, z, t_d, z_d, c), fd = shifted_rms(t, z, t_d, z_d, d);
  while (b - a > 1e-7) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = shifted_rms(t, z, t_d, z_d, c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = shifted_rms(t, z, t_d, z_d, d);
    }
  }
  const double polished = 0.5 * (a + b);
  return shifted_rms(t, z, t_d, z_d, polished) <= best_rms ? polished : best;
}

CalibrationStudy load_calibration_study(const std::string& path, const CalibrationOverrides& o) {
  const io::Json json = io::read_json_file(path);
  const io::JsonReader r(json, path);
  CalibrationStudy s;
  s.common = parse_study_common(r, "calibration");
  if (o.data_path.empty() && !r.has("data")) r.fail("data", "missing: give the measured curve here or with --data");
  s.data_path = o.data_path.empty() ? io::resolve_relative(path, r.string("data")) : o.data_path;
  (void)r.has("data");  // allowed to be absent when --data is given
  const io::CsvTable table = io::read_csv(s.data_path, {"t", "z"});
  s.data_t = table.column("t");
  s.data_z = table.column("z");

  std::vector<std::string> names;
  if (!o.fit.empty()) {
    names = o.fit;
    (void)r.has("fit");
  } else {
    const io::Json& fit = r.raw("fit");
    if (!fit.is_array() || fit.empty()) r.fail("fit", "expected a non-empty list of parameter names");
    for (const auto& n : fit) {
      if (!n.is_string()) r.fail("fit", "expected parameter names (strings)");
      names.push_back(n.get<std::string>());
    }
  }
  const io::JsonReader bounds = r.child("bounds");
  const io::JsonReader initial = r.child("initial");
  for (const std::string& name : names) {
    if (std::find(kFittable.begin(), kFittable.end(), name) == kFittable.end())
      r.fail("fit", "unknown parameter '" + name + "' (can fit: c_q, f, M0_scale, time_offset)");
    for (const auto& p : s.fit)
      if (p.name == name) r.fail("fit", "parameter '" + name + "' is listed twice");
    FitParameter p;
    p.name = name;
    p.log_scale = name == "f";
    const auto b = bounds.fixed_numbers<2>(name);
    p.lower = b[0];
    p.upper = b[1];
    if (!(p.lower < p.upper)) bounds.fail(name, "bounds reversed or empty: lower must be below upper");
    if (p.log_scale && !(p.lower > 0)) bounds.fail(name, "bounds of f must be positive");
    p.initial = initial.number(name);
    if (p.initial < p.lower || p.initial > p.upper) initial.fail(name, "initial value outside the bounds");
    s.fit.push_back(p);
  }
  // Bounds and initial values of parameters not fitted are accepted (a study
  // file lists them all so --fit can choose); the offset range is always used.
  for (const std::string& name : kFittable) {
    if (bounds.has(name)) {
      const auto b = bounds.fixed_numbers<2>(name);
      if (!(b[0] < b[1])) bounds.fail(name, "bounds reversed or empty: lower must be below upper");
      if (name == "time_offset") {
        s.offset_min_s = b[0];
        s.offset_max_s = b[1];
      }
    }
    if (initial.has(name) && name == "time_offset") s.offset_initial_s = initial.number(name);
    else if (initial.has(name)) initial.number(name);
  }
  bounds.finish();
  initial.finish();
  // Read every key even when the command line overrides it (no "unknown key").
  const std::string configured_algorithm = r.string_or("algorithm", "LN_BOBYQA");
  const int configured_evaluations = r.integer_or("max_evaluations", 40);
  const int configured_starts = r.integer_or("starts", 1);
  s.algorithm = !o.algorithm.empty() ? o.algorithm : configured_algorithm;
  if (static_cast<int>(nlopt_algorithm_from_string(s.algorithm.c_str())) < 0)
    r.fail("algorithm", "unknown NLopt algorithm '" + s.algorithm + "' (e.g. LN_BOBYQA, LN_NELDERMEAD, GN_DIRECT_L, GN_CRS2_LM)");
  s.max_evaluations = o.max_evaluations > 0 ? o.max_evaluations : configured_evaluations;
  if (s.max_evaluations <= 0) r.fail("max_evaluations", "must be positive");
  s.xtol_rel = r.has("xtol_rel") ? r.positive("xtol_rel") : 1e-3;
  s.starts = o.starts > 0 ? o.starts : configured_starts;
  if (s.starts <= 0) r.fail("starts", "must be positive");
  s.seed = static_cast<std::uint64_t>(r.integer_or("seed", 1));
  r.finish();
  return s;
}

std::string run_calibration(const CalibrationStudy& s, const StudyRunControl& control) {
  const std::string out = results_path(s.common, control.results_path);
  const std::size_t p = s.fit.size();
  const std::size_t row = p + 3;  // parameters, offset, rms, status

  // One task = one local (or global) NLopt search from its own start point;
  // its values are the history of every evaluation, row by row.
  auto compute = [&](int start) {
    std::vector<double> x(p), lower(p), upper(p);
    boost::random::mt19937_64 engine(s.seed * 1000003ull + static_cast<std::uint64_t>(start));
    for (std::size_t k = 0; k < p; ++k) {
      const FitParameter& f = s.fit[k];
      lower[k] = to_internal(f, f.lower);
      upper[k] = to_internal(f, f.upper);
      x[k] = start == 0 ? to_internal(f, f.initial)
                        : boost::random::uniform_real_distribution<double>(lower[k], upper[k])(engine);
    }
    std::vector<double> history;
    std::function<double(const std::vector<double>&)> objective = [&](const std::vector<double>& xi) {
      std::vector<double> values(p);
      for (std::size_t k = 0; k < p; ++k) values[k] = to_natural(s.fit[k], xi[k]);
      const Evaluation e = evaluate(s, values);
      history.insert(history.end(), values.begin(), values.end());
      history.push_back(e.offset);
      history.push_back(e.rms);
      history.push_back(e.status);
      return e.rms;
    };
    nlopt::opt opt(s.algorithm.c_str(), static_cast<unsigned>(p));
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
    opt.set_maxeval(s.max_evaluations);
    opt.set_xtol_rel(s.xtol_rel);
    if (s.algorithm.find("MLSL") != std::string::npos || s.algorithm.find("AUGLAG") != std::string::npos) {
      nlopt::opt local(nlopt::LN_BOBYQA, static_cast<unsigned>(p));
      local.set_xtol_rel(s.xtol_rel);
      opt.set_local_optimizer(local);
    }
    nlopt::srand(s.seed + static_cast<unsigned long>(start));
    opt.set_min_objective(
        [](const std::vector<double>& xi, std::vector<double>& /*grad*/, void* data) {
          return (*static_cast<std::function<double(const std::vector<double>&)>*>(data))(xi);
        },
        &objective);
    double best = 0.0;
    TaskResult result{start, 0, "", {}};
    try {
      const nlopt::result code = opt.optimize(x, best);
      result.message = std::string("nlopt: ") + nlopt_result_to_string(static_cast<nlopt_result>(code));
    } catch (const nlopt::roundoff_limited&) {
      result.message = "nlopt: roundoff limited (the result is as good as it gets)";
    } catch (const std::exception& e) {
      if (history.empty()) throw;
      result.message = std::string("nlopt stopped: ") + e.what();
    }
    result.values = std::move(history);
    return result;
  };
  StudyRunOptions options{.results_path = out, .fingerprint = s.common.fingerprint, .resume = control.resume,
                          .label = "calibrate", .progress_interval_s = control.progress_interval_s,
                          .resume_command = control.resume_command, .checkpoint = control.checkpoint};
  const std::vector<TaskResult> results = run_study_tasks(s.starts, compute, options);
  if (world_rank() != 0) return out;

  // Every evaluation of every start, and the best of them.
  std::vector<double> history, history_start;
  std::size_t best_row = 0;
  double best_rms = std::numeric_limits<double>::infinity();
  std::vector<std::string> messages;
  for (const TaskResult& r : results) {
    messages.push_back("start " + std::to_string(r.index) + ": " + r.message);
    for (std::size_t k = 0; k + row <= r.values.size(); k += row) {
      const std::size_t e = history.size() / row;
      history.insert(history.end(), r.values.begin() + static_cast<std::ptrdiff_t>(k),
                     r.values.begin() + static_cast<std::ptrdiff_t>(k + row));
      history_start.push_back(r.index);
      if (r.values[k + p + 2] == 0 && r.values[k + p + 1] < best_rms) {
        best_rms = r.values[k + p + 1];
        best_row = e;
      }
    }
  }
  if (history.empty()) throw std::runtime_error("calibrate: no evaluation finished");
  const std::vector<double> best_values(history.begin() + static_cast<std::ptrdiff_t>(best_row * row),
                                        history.begin() + static_cast<std::ptrdiff_t>(best_row * row + p));
  const double best_offset_s = history[best_row * row + p];
  const Trajectory fit = simulate(s.common.setup.model, s.common.setup.scenario, inputs_for(s, best_values));
  std::vector<double> fit_t(fit.t.size());
  for (std::size_t i = 0; i < fit.t.size(); ++i) fit_t[i] = fit.t[i] + best_offset_s;

  std::vector<std::string> names, columns;
  for (const auto& f : s.fit) names.push_back(f.name);
  columns = names;
  columns.insert(columns.end(), {"time_offset", "rms", "status"});
  io::Hdf5Writer h5(out);
  h5.write("/history", history, history.size() / row, row);
  h5.write("/history_columns", columns);
  h5.write("/history_start", history_start);
  h5.write("/best/values", best_values);
  h5.write("/best/names", names);
  h5.write("/best/time_offset", std::vector<double>{best_offset_s});
  h5.write("/best/rms", std::vector<double>{best_rms});
  h5.write("/data/t", s.data_t);
  h5.write("/data/z", s.data_z);
  h5.write("/fit/t", fit_t);
  h5.write("/fit/z", fit.B_l_z);
  h5.write("/messages", messages);
  write_study_provenance(h5, s.common);
  h5.attribute("/", "data_file", s.data_path);
  h5.attribute("/", "algorithm", s.algorithm);
  h5.attribute("/", "max_evaluations", static_cast<long long>(s.max_evaluations));
  h5.attribute("/", "starts", static_cast<long long>(s.starts));
  h5.commit();
  remove_checkpoint(out);
  std::cerr << "calibrate: " << history.size() / row << " evaluations; best RMS " << best_rms * 1000.0
            << " mm at";
  for (std::size_t k = 0; k < p; ++k) std::cerr << " " << names[k] << " = " << best_values[k];
  std::cerr << ", time offset " << best_offset_s << " s; wrote " << out << "\n";

  if (control.plot) {
    const std::string png = out.substr(0, out.size() - 3) + ".png";
    io::LinePlot plot;
    plot.title = s.common.name + ": data and fitted B_l z (RMS " + std::to_string(best_rms * 1000.0).substr(0, 6) + " mm)";
    plot.x_label = "t (data clock) [s]";
    plot.y_label = "B_l z [mm]";
    io::Series data, model;
    data.label = "data";
    data.x = s.data_t;
    for (double z : s.data_z) data.y.push_back(1000.0 * z);
    data.style = io::SeriesStyle::points;
    model.label = "fitted model";
    model.x = fit_t;
    for (double z : fit.B_l_z) model.y.push_back(1000.0 * z);
    plot.series = {data, model};
    io::write_png_or_warn(plot, png, "calibrate", std::cerr);
  }
  return out;
}

}  // namespace rover::study
