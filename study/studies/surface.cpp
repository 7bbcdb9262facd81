// See surface.hpp: the study's configuration and runs.
#include "study/studies/surface.hpp"

#include <algorithm>
#include <cmath>

#include "core/number_text.hpp"
#include "core/reference_miss.hpp"
#include "core/simulate.hpp"
#include "io/config_kind.hpp"
#include "io/trajectory_io.hpp"
#include "io/output_target.hpp"
#include "study/design/design.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/calibration.hpp"
#include "study/studies/study_output.hpp"
#include "study/studies/study_spec.hpp"

namespace rover::study {
namespace {

constexpr int kMaxAxisPoints = 1'000'000;
constexpr double kMaxGridPoints = 1e6;
constexpr double kMaxReferenceHeightM = 1e3;
// Neighbouring grid values closer than this (relative) are one value to the model.
constexpr double kMinRelativeSpacing = 1e-12;
// A line through two points fits them exactly (r^2 = 1 whatever the timing):
// the sweep's regression is judged on three f values or more.
constexpr int kMinSweepPoints = 3;
// The exit status of a surface whose kriged map is not to be trusted (README
// "Guarantees": a result not to be trusted).
constexpr int kUntrustedMapStatus = 2;
const std::vector<std::string> kSurfaceInputs{"s_structure.f", "s_structure.c_q"};

std::vector<double> parse_axis(const io::JsonReader& parent, const std::string& key, bool* log_spacing = nullptr) {
  const io::JsonReader a = parent.child(key);
  const std::string spacing = a.string_or("spacing", "linear");
  if (spacing != "log" && spacing != "linear") a.fail("spacing", "must be 'linear' or 'log'");
  // A linear axis may start at 0 (no damping); a log axis needs positive ends.
  if (spacing == "log")
    for (const char* end : {"min", "max"})
      if (const double v = a.number(end); !(v > 0.0))
        a.fail(end, "must be > 0 on a log-spaced axis (\"spacing\": \"log\"), got " + number_text(v) + ": give a " +
                        "positive " + end + (v == 0.0 ? ", or \"spacing\": \"linear\" to include 0" : ""));
  const double min = spacing == "log" ? a.positive("min") : a.non_negative("min");
  const double max = spacing == "log" ? a.positive("max") : a.non_negative("max");
  const int count = a.integer("count", {1, kMaxAxisPoints});
  if (!(max >= min)) a.fail("max", "must not be below min (" + number_text(min) + ")");
  if (count == 1 && max > min)
    a.fail("count", "1 point runs min = " + number_text(min) + " only, and max = " + number_text(max) +
                        " would be ignored: give count 2 or more, or max equal to min");
  if (count > 1 && !(max > min))
    a.fail("count", std::to_string(count) + " points between min = max = " + number_text(min) +
                        " would be identical runs: give count 1, or max above min");
  const std::vector<double> v = spacing == "log" ? log_grid(min, max, count) : linear_grid(min, max, count);
  for (std::size_t i = 1; i < v.size(); ++i)
    if (!(v[i] - v[i - 1] > kMinRelativeSpacing * v[i]))
      a.fail("count", std::to_string(count) + " points between " + exact_number_text(min) + " and " +
                          exact_number_text(max) + " lie closer than " + number_text(kMinRelativeSpacing) +
                          " of their size (" + exact_number_text(v[i - 1]) + " and " + exact_number_text(v[i]) +
                          "): their runs would differ by rounding only; widen the axis or give fewer points");
  if (log_spacing != nullptr) *log_spacing = spacing == "log";
  a.finish();
  return v;
}

// Refuses, before any run, a grid or sweep whose ends the model refuses (an
// f or c_q beyond the S-structure's bounds, core/model_scale.hpp): every run
// there would fail. Each end is tried with the other axis at its first value.
void refuse_points_the_model_refuses(const io::JsonReader& r, const SurfaceStudy& s) {
  const RoverStudyModel model(s.sources, kSurfaceInputs, {}, {}, s.integrator);
  auto try_point = [&](const std::string& field, double f, double c_q) {
    const double point[2] = {f, c_q};
    try {
      (void)model.setup_at(point);
    } catch (const std::exception& e) {
      r.fail(field, "the run at f = " + number_text(f) + ", c_q = " + number_text(c_q) + " is refused: " + e.what());
    }
  };
  for (double f : {s.f.front(), s.f.back()}) try_point("f", f, s.c_q.front());
  for (double c_q : {s.c_q.front(), s.c_q.back()}) try_point("c_q", s.f.front(), c_q);
  if (s.sweep_f.empty()) return;
  try_point("sweep.c_q", s.f.front(), s.sweep_c_q);  // at an f the grid's check took
  for (double f : {s.sweep_f.front(), s.sweep_f.back()}) try_point("sweep.f", f, s.sweep_c_q);
}

// The reference curve: the study's file, or the run at its (f, c_q).
std::shared_ptr<ReferenceCurve> reference_curve(const SurfaceStudy& study) {
  auto reference = std::make_shared<ReferenceCurve>();
  reference->path = study.reference_description;
  if (!study.simulate_reference) {
    reference->t = study.reference_t;
    reference->value = study.reference_z;
    return reference;
  }
  const RoverStudyModel reference_model(study.sources, kSurfaceInputs, {}, {Channel::kBlz}, study.integrator);
  const double point[2] = {study.reference_f, study.reference_c_q};
  RunRecord failure;
  const std::optional<Trajectory> tr = reference_model.simulate_at(point, &failure);
  if (!tr || !tr->ok())
    throw std::runtime_error(study.path + ": field 'reference.simulate': the reference run failed: " +
                             (tr ? tr->message : failure.message));
  reference->t = tr->t;
  reference->value = tr->B_l_z;
  return reference;
}

// The run RMS values (grid and kriging design) all beyond the span of the
// reference's heights: the warning that says so, else "".
std::string reference_missed_warning(const SurfaceResult& r, const ReferenceCurve& reference) {
  std::vector<double> rms(r.rms.data(), r.rms.data() + r.rms.size());
  rms.insert(rms.end(), r.kriging.rms.data(), r.kriging.rms.data() + r.kriging.rms.size());
  const double span = value_span(reference.value);
  if (!every_rms_exceeds_span(rms, span)) return "";
  return "rms: " + reference_missed_text("every run misses", reference.path, span, "m", "B_l z channel");
}

int grid_tasks(const SurfaceStudy& study) {
  return study.runs_grid() ? static_cast<int>(study.f.size() * study.c_q.size()) : 0;
}

// The runs: the grid (when it is run), f major, then the sweep, then the
// kriging design.
DesignMatrix surface_design(const SurfaceStudy& study) {
  const auto nc = study.c_q.size();
  const int grid = grid_tasks(study);
  const int sweep_end = grid + static_cast<int>(study.sweep_f.size());
  const DesignMatrix kriging =
      study.kriging.enabled ? surface_kriging_design(study.kriging) : DesignMatrix(0, 2);
  DesignMatrix x(sweep_end + kriging.rows(), 2);
  for (int i = 0; i < grid; ++i)
    x.row(i) << study.f[static_cast<std::size_t>(i) / nc], study.c_q[static_cast<std::size_t>(i) % nc];
  for (int i = grid; i < sweep_end; ++i)
    x.row(i) << study.sweep_f[static_cast<std::size_t>(i - grid)], study.sweep_c_q;
  x.bottomRows(kriging.rows()) = kriging;
  return x;
}

// Collects the runs' records, in any order, into the result.
class SurfaceCollector {
 public:
  SurfaceCollector(SurfaceResult& result, int nf, int nc, int grid_tasks, const DesignMatrix& kriging_x)
      : r_(result), nc_(nc), grid_tasks_(grid_tasks),
        kriging_first_(grid_tasks + static_cast<int>(result.study.sweep_f.size())) {
    const double nan = std::nan("");
    r_.rms = Eigen::MatrixXd::Constant(nf, nc, nan);
    r_.t_c = r_.rms;
    r_.rhs_evaluations = r_.rms;
    r_.status.assign(static_cast<std::size_t>(grid_tasks_), 0);
    r_.messages.assign(static_cast<std::size_t>(grid_tasks_), "");
    r_.sweep_t_c.assign(r_.study.sweep_f.size(), nan);
    r_.sweep_rhs_evaluations = r_.sweep_t_c;
    SurfaceKriging& k = r_.kriging;
    k.x = kriging_x;
    k.rms = Eigen::VectorXd::Constant(kriging_x.rows(), nan);
    k.t_c = k.rms;
    k.status.assign(static_cast<std::size_t>(kriging_x.rows()), run_status::kError);
    k.messages.assign(static_cast<std::size_t>(kriging_x.rows()), "");
  }

  void add(int i, const RunRecord& record) {
    ++r_.runs;
    r_.failed += record.ok() ? 0 : 1;
    if (!record.ok() && (r_.first_failure_task < 0 || i < r_.first_failure_task)) {
      r_.first_failure_task = i;
      r_.first_failure = record.message;
    }
    if (i >= kriging_first_) {
      SurfaceKriging& k = r_.kriging;
      const Eigen::Index row = i - kriging_first_;
      k.status[static_cast<std::size_t>(row)] = record.status;
      k.messages[static_cast<std::size_t>(row)] = record.message;
      if (!record.ok()) return;
      k.rms(row) = record.qoi[0];
      k.t_c(row) = record.wall_time_s;
      return;
    }
    if (i >= grid_tasks_) {
      if (!record.ok()) return;
      const auto k = static_cast<std::size_t>(i - grid_tasks_);
      r_.sweep_t_c[k] = record.wall_time_s;
      r_.sweep_rhs_evaluations[k] = record.rhs_evaluations;
      return;
    }
    r_.status[static_cast<std::size_t>(i)] = record.status;
    r_.messages[static_cast<std::size_t>(i)] = record.message;
    if (!record.ok()) return;
    r_.rms(i / nc_, i % nc_) = record.qoi[0];
    r_.t_c(i / nc_, i % nc_) = record.wall_time_s;
    r_.rhs_evaluations(i / nc_, i % nc_) = record.rhs_evaluations;
  }

 private:
  SurfaceResult& r_;
  int nc_, grid_tasks_, kriging_first_;
};

LinearFit sweep_regression(const SurfaceResult& r) {
  std::vector<double> f, t_c;
  for (std::size_t k = 0; k < r.study.sweep_f.size(); ++k)
    if (std::isfinite(r.sweep_t_c[k])) {
      f.push_back(r.study.sweep_f[k]);
      t_c.push_back(r.sweep_t_c[k]);
    }
  return linear_regression(f, t_c);
}

// The "reference" block: a curve file (checked against the run's duration_s,
// its time offset applied) or
// the (f, c_q) of a simulated reference. Returns its text for the fingerprint.
std::string parse_reference(const io::JsonReader& ref, const ModelInputs& nominal, double duration_s, SurfaceStudy& s) {
  if (ref.has("file") == ref.has("simulate"))
    ref.fail("file", "give exactly one of 'file' (a measured or simulated curve) and 'simulate'");
  if (ref.has("file")) {
    const std::string file = io::resolve_relative(s.path, ref.string("file"));
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
      if (!std::isfinite(z) || std::abs(z) > kMaxReferenceHeightM) ref.fail("file", file + ": values must be finite heights in metres");
    const double offset = ref.number_or("time_offset", 0.0);
    if (const std::string p = reference_span_problem(c.t, offset, duration_s); !p.empty())
      ref.fail("file", file + " " + p + " (run: " + s.sources.scenario_path + ")");
    if (const std::string p = constant_reference_problem(c.y); !p.empty()) ref.fail("file", file + ": " + p);
    for (double& t : c.t) t -= offset;
    s.reference_t = c.t;
    s.reference_z = c.y;
    s.reference_description = "file " + file;
    s.files.add(file, "'reference.file' in " + s.path);
    ref.finish();
    return file_text(file) + "|offset " + std::to_string(offset);
  }
  const io::JsonReader sim = ref.child("simulate");
  const ModelInputs in = io::parse_simulation_inputs(sim, nominal);
  s.simulate_reference = true;
  s.reference_f = in.sharpness_f;
  s.reference_c_q = in.damping_c_q;
  s.reference_description = "simulated at f = " + number_text(in.sharpness_f) +
                            ", c_q = " + number_text(in.damping_c_q);
  ref.finish();
  return s.reference_description;
}

// The kriged maps, checked against the grid's runs or a surface result file.
void krige(const SurfaceStudy& study, SurfaceResult& result) {
  fit_surface_kriging(study.kriging, study.f, study.c_q, result.kriging);
  if (study.kriging.check_grid) {
    check_surface_kriging(result.rms, result.t_c, "the grid's runs", result.kriging);
  } else if (!study.kriging.check_file.empty()) {
    Eigen::MatrixXd rms, t_c;
    read_surface_check(study.kriging.check_file, study.f, study.c_q, study.runs_key, rms, t_c);
    check_surface_kriging(rms, t_c, study.kriging.check_file, result.kriging);
  }
}

}  // namespace

LinearFit linear_regression(const std::vector<double>& x, const std::vector<double>& y) {
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
  // r^2 of fewer than 3 points, or of a constant t_c, says nothing: none.
  const double r2 = x.size() >= static_cast<std::size_t>(kMinSweepPoints) && syy > 0 ? (sxy * sxy) / (sxx * syy) : std::nan("");
  return {a, b, r2};
}

SurfaceStudy load_surface_study(const std::string& path) {
  const io::Json json = io::read_config_file(path, io::ConfigKind::kStudy);
  const io::JsonReader r(json, path);
  SurfaceStudy s;
  s.path = path;
  s.name = parse_study_identity(r, {"surface"}).name;
  const std::string scenario = io::resolve_relative(path, r.string("scenario"));
  io::ScenarioSetup nominal;
  try {
    s.sources = io::read_scenario_sources(scenario);
    nominal = io::build_scenario(s.sources);
    s.files.add(scenario, "'scenario' in " + path);
    s.files.add_all(s.sources.files);
  } catch (const io::ConfigError& e) {
    r.fail("scenario", e.what());
  }
  if (r.has("integrator")) {
    s.integrator = io::parse_integrator_settings(r.child("integrator"), nominal.scenario.integrator);
    refuse_integrator_the_scenario_refuses(r, "integrator", nominal.scenario, *s.integrator);
  }
  bool f_log = false, c_q_log = false;
  s.f = parse_axis(r, "f", &f_log);
  s.c_q = parse_axis(r, "c_q", &c_q_log);
  s.kriging = parse_surface_kriging(r, path, s.f.front(), s.f.back(), f_log, s.c_q.front(), s.c_q.back(), c_q_log);
  if (!s.kriging.check_file.empty()) s.files.add(s.kriging.check_file, "'check.file' in " + path);
  if (static_cast<double>(s.f.size()) * static_cast<double>(s.c_q.size()) > kMaxGridPoints)
    r.fail("f", "the grid would have more than 1e6 points");
  if (r.has("sweep")) {
    const io::JsonReader sw = r.child("sweep");
    s.sweep_f = parse_axis(sw, "f");
    if (s.sweep_f.size() < static_cast<std::size_t>(kMinSweepPoints))
      sw.child("f").fail("count", std::to_string(s.sweep_f.size()) + " point(s): a line through " +
                                      "fewer than 3 fits them exactly (r^2 = 1 whatever t_c does); give count 3 or more");
    s.sweep_c_q = sw.non_negative("c_q");
    sw.finish();
  }
  const std::string reference_text = parse_reference(r.child("reference"), nominal.inputs, nominal.scenario.duration_s, s);
  s.runs_key = io::config_fingerprint(file_text(scenario) + file_text(s.sources.rover_path) +
                                      file_text(s.sources.terrain_path) + reference_text);
  if (!s.kriging.check_file.empty()) {  // refused before any run, not after
    Eigen::MatrixXd rms, t_c;
    try {
      read_surface_check(s.kriging.check_file, s.f, s.c_q, s.runs_key, rms, t_c);
    } catch (const std::exception& e) {
      r.fail("check", e.what());
    }
  }
  r.finish();
  refuse_points_the_model_refuses(r, s);
  s.fingerprint = io::config_fingerprint(file_text(path) + file_text(scenario) + file_text(s.sources.rover_path) +
                                         file_text(s.sources.terrain_path) + reference_text);
  return s;
}

SurfaceResult run_surface(const SurfaceStudy& study, const StudyRuntime& runtime) {
  QoiSpec rms;
  rms.name = "rms";
  rms.kind = QoiKind::kRmsVs;
  rms.reference = reference_curve(study);
  const RoverStudyModel model(study.sources, kSurfaceInputs, {rms}, {}, study.integrator);
  const DesignMatrix x = surface_design(study);
  SurfaceResult result;
  result.study = study;
  result.integrator = model.nominal().scenario.integrator;
  result.scenario_name = model.nominal().scenario.name;
  const int grid = grid_tasks(study);
  const int kriging_runs = study.kriging.enabled ? study.kriging.runs : 0;
  SurfaceCollector collector(result, static_cast<int>(study.f.size()), static_cast<int>(study.c_q.size()), grid,
                             x.bottomRows(kriging_runs));
  const RecordLayout layout = model.layout();
  auto compute = [&](int i) { return encode_record(i, model.run(x.row(i).data())); };
  auto consume = [&](TaskResult&& task) {
    const int i = task.index;
    collector.add(i, decode_record(layout, std::move(task)));
  };
  stream_study_tasks(static_cast<int>(x.rows()), compute, consume, runtime.options);
  if (world_rank() != 0) return {};
  result.regression = sweep_regression(result);
  if (study.kriging.enabled) krige(study, result);
  result.reference_warning = reference_missed_warning(result, *rms.reference);
  return result;
}

StudyProgram<SurfaceResult> surface_program(SurfaceStudy study) {
  StudyProgram<SurfaceResult> p;
  p.command = "surface";
  p.name = study.name;
  p.fingerprint = study.fingerprint;
  p.inputs = study.files;
  p.banner = std::to_string(study.f.size()) + " x " + std::to_string(study.c_q.size()) + " grid" +
             (study.kriging.enabled ? std::string(study.runs_grid() ? " (run and kriged" : " (kriged") + " from " +
                                          std::to_string(study.kriging.runs) + " Latin hypercube runs)"
                                    : std::string()) +
             " + " + std::to_string(study.sweep_f.size()) + " sweep runs of " + study.sources.scenario_path +
             " on " + describe_integrator(study.integrator.value_or(io::build_scenario(study.sources).scenario.integrator)) +
             ", on " + std::to_string(world_size()) + " rank(s)";
  p.run = [study](const StudyRuntime& runtime) { return run_surface(study, runtime); };
  p.write = write_surface;
  p.counts = [](const SurfaceResult& r) {
    RunCounts c = count_runs(r.status, r.messages);  // the grid's notes
    c.runs = r.runs;  // the grid's, the sweep's and the kriging design's runs
    c.failed = r.failed;
    c.first_failure = r.first_failure;
    return c;
  };
  p.plot = plot_surface;
  p.figures = [study](PlotSelection plots) { return surface_figures(study, plots); };
  // A kriged map the report calls not to be trusted is a result not to be trusted.
  p.verdict = [](const SurfaceResult& r) {
    const auto& maps = r.kriging.maps;
    return std::any_of(maps.begin(), maps.end(), surface_map_not_to_trust) ? kUntrustedMapStatus : 0;
  };
  p.report = [](const SurfaceResult& r, std::ostream& out) {
    if (r.study.kriging.enabled) report_surface_kriging(r.kriging, out);
    if (!r.reference_warning.empty()) out << "surface: warning: " << r.reference_warning << "\n";
  };
  return p;
}

}  // namespace rover::study
