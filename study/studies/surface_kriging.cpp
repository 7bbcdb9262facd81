// See surface_kriging.hpp.
#include "study/studies/surface_kriging.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <ostream>
#include <stdexcept>

#include "io/scenario_config.hpp"
#include "study/design/design.hpp"
#include "study/runtime/run_record.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/surrogate_file.hpp"

namespace rover::study {
namespace {

constexpr int kMaxSurfaceKrigingRuns = 5000;  // the process's n x n matrices
constexpr int kMaxStarts = 100;
// The likelihood with an estimated nugget has several optima: more starts.
constexpr int kSurfaceKrigingStarts = 12;
// A wall time on a shared machine can be as noisy as its trend is large.
constexpr double kSurfaceKrigingMaxNugget = 1.0;
// Two grids agree when every axis value does to this relative tolerance.
constexpr double kGridTolerance = 1e-9;
const char* const kQoiNames[2] = {"rms", "t_c"};

std::vector<Eigen::Index> ok_runs(const SurfaceKriging& k, const Eigen::VectorXd& y) {
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < y.size(); ++i)
    if (k.status[static_cast<std::size_t>(i)] == run_status::kOk && std::isfinite(y(i))) rows.push_back(i);
  return rows;
}

// nf x nc from the grid's points, f major.
Eigen::MatrixXd grid_map(const Eigen::VectorXd& v, Eigen::Index nf, Eigen::Index nc) {
  return Eigen::Map<const Eigen::MatrixXd>(v.data(), nc, nf).transpose();
}

SurfaceKrigingMap fit_map(const SurfaceKrigingSpec& spec, const SurfaceKriging& k, const Eigen::VectorXd& y,
                          const std::string& name, bool log_scale, const DesignMatrix& grid, Eigen::Index nf,
                          Eigen::Index nc) {
  SurfaceKrigingMap m;
  m.name = name;
  m.log_scale = log_scale;
  m.wall_time = name == kQoiNames[1];
  const std::vector<Eigen::Index> rows = ok_runs(k, y);
  DesignMatrix x(static_cast<Eigen::Index>(rows.size()), 2);
  Eigen::VectorXd v(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    x.row(static_cast<Eigen::Index>(r)) = k.x.row(rows[r]);
    v(static_cast<Eigen::Index>(r)) = y(rows[r]);
  }
  if (log_scale && !(v.array() > 0.0).all()) {
    m.undefined_reason = name + " is not positive in every run: it cannot be kriged in log scale";
    return m;
  }
  if (log_scale) v = v.array().log();
  try {
    m.model = fit_gaussian_process_surrogate(x, v, spec.inputs, interruptible(spec.gp), log_scale ? "log_" + name : name);
    m.fitted = true;
  } catch (const std::invalid_argument& e) {
    m.undefined_reason = e.what();
    return m;
  }
  const SurrogatePrediction p = predict_surrogate(m.model, grid);
  const double nugget_variance = m.model.gp.nugget * m.model.gp.process_variance;
  const Eigen::VectorXd sd = (p.sd.array().square() + nugget_variance).sqrt();
  const Eigen::VectorXd lower = p.mean - kSurfaceCoverageSds * sd, upper = p.mean + kSurfaceCoverageSds * sd;
  m.sd = grid_map(sd, nf, nc);
  m.mean = grid_map(log_scale ? Eigen::VectorXd(p.mean.array().exp()) : p.mean, nf, nc);
  m.lower = grid_map(log_scale ? Eigen::VectorXd(lower.array().exp()) : lower, nf, nc);
  m.upper = grid_map(log_scale ? Eigen::VectorXd(upper.array().exp()) : upper, nf, nc);
  return m;
}

void check_map(const Eigen::MatrixXd& actual, SurfaceKrigingMap& m) {
  m.checked = true;
  m.actual = actual;
  m.error = m.mean - actual;
  double sse = 0.0, sum = 0.0, sum_sq = 0.0;
  m.checked_points = m.covered_points = 0;
  m.max_abs_error = 0.0;
  for (Eigen::Index i = 0; i < actual.rows(); ++i)
    for (Eigen::Index j = 0; j < actual.cols(); ++j) {
      if (!std::isfinite(actual(i, j))) continue;
      const double e = m.error(i, j);
      ++m.checked_points;
      m.covered_points += actual(i, j) >= m.lower(i, j) && actual(i, j) <= m.upper(i, j) ? 1 : 0;
      m.max_abs_error = std::max(m.max_abs_error, std::abs(e));
      sse += e * e;
      sum += actual(i, j);
      sum_sq += actual(i, j) * actual(i, j);
    }
  const double n = static_cast<double>(m.checked_points);
  const double sst = sum_sq - sum * sum / std::max(n, 1.0);
  m.q2 = sst > 0.0 ? 1.0 - sse / sst : std::nan("");
  m.coverage = m.checked_points > 0 ? m.covered_points / n : std::nan("");
}

bool same_axis(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::abs(a[i] - b[i]) > kGridTolerance * std::max(std::abs(a[i]), std::abs(b[i]))) return false;
  return true;
}

}  // namespace

SurfaceKrigingSpec parse_surface_kriging(const io::JsonReader& r, const std::string& study_path, double f_min,
                                         double f_max, bool f_log, double c_q_min, double c_q_max, bool c_q_log) {
  SurfaceKrigingSpec s;
  if (!r.has("surrogate")) {
    for (const char* key : {"runs", "check", "gp"})
      if (r.has(key)) r.fail(key, "applies to a kriged surface (\"surrogate\": \"gp\")");
    return s;
  }
  const std::string kind = r.string("surrogate");
  if (kind != "gp") r.fail("surrogate", "expected \"gp\" (kriging of the surface from \"runs\" runs), got \"" + kind + "\"");
  s.enabled = true;
  s.runs = r.integer("runs", {kMinSurfaceKrigingRuns, kMaxSurfaceKrigingRuns});
  s.seed = r.seed_or("seed", s.seed);
  if (r.has("check")) {
    if (r.raw("check").is_string()) {
      const std::string check = r.string("check");
      if (check != "grid") r.fail("check", "expected \"grid\" or {\"file\": <surface result>}, got \"" + check + "\"");
      s.check_grid = true;
    } else {
      const io::JsonReader c = r.child("check");
      s.check_file = io::resolve_relative(study_path, c.string("file"));
      c.finish();
    }
  }
  s.gp.estimate_nugget = true;
  s.gp.starts = kSurfaceKrigingStarts;
  s.gp.max_nugget = kSurfaceKrigingMaxNugget;
  s.gp.seed = s.seed;
  if (r.has("gp")) {
    const io::JsonReader g = r.child("gp");
    const std::string trend = g.string_or("trend", "constant");
    if (trend == "linear") s.gp.trend = KrigingTrend::kLinear;
    else if (trend != "constant") g.fail("trend", "expected \"constant\" or \"linear\", got \"" + trend + "\"");
    s.gp.starts = g.integer_or("starts", s.gp.starts, {1, kMaxStarts});
    g.finish();
  }
  if (!(f_max > f_min) || !(c_q_max > c_q_min))
    r.fail("surrogate", "a kriged surface needs axes with max > min");
  s.inputs = {f_log ? log_uniform(f_min, f_max) : uniform(f_min, f_max),
              c_q_log ? log_uniform(c_q_min, c_q_max) : uniform(c_q_min, c_q_max)};
  return s;
}

DesignMatrix surface_kriging_design(const SurfaceKrigingSpec& spec) {
  return map_to_distributions(unit_design(DesignType::kLatinHypercube, spec.runs, 2, spec.seed), spec.inputs);
}

void fit_surface_kriging(const SurfaceKrigingSpec& spec, const std::vector<double>& f, const std::vector<double>& c_q,
                         SurfaceKriging& k) {
  const auto nf = static_cast<Eigen::Index>(f.size()), nc = static_cast<Eigen::Index>(c_q.size());
  DesignMatrix grid(nf * nc, 2);
  for (Eigen::Index i = 0; i < nf; ++i)
    for (Eigen::Index j = 0; j < nc; ++j)
      grid.row(i * nc + j) << f[static_cast<std::size_t>(i)], c_q[static_cast<std::size_t>(j)];
  k.maps.clear();
  k.maps.push_back(fit_map(spec, k, k.rms, kQoiNames[0], /*log_scale=*/false, grid, nf, nc));
  k.maps.push_back(fit_map(spec, k, k.t_c, kQoiNames[1], /*log_scale=*/true, grid, nf, nc));
}

void check_surface_kriging(const Eigen::MatrixXd& rms, const Eigen::MatrixXd& t_c, const std::string& source,
                           SurfaceKriging& k) {
  k.check_source = source;
  for (SurfaceKrigingMap& m : k.maps)
    if (m.fitted) check_map(m.name == kQoiNames[0] ? rms : t_c, m);
}

void read_surface_check(const std::string& path, const std::vector<double>& f, const std::vector<double>& c_q,
                        const std::string& runs_key, Eigen::MatrixXd& rms, Eigen::MatrixXd& t_c) {
  const auto fail = [&](const std::string& what) { throw io::ConfigError(path + ": check: " + what); };
  if (!std::filesystem::is_regular_file(path)) fail("no such surface result file");
  const io::Hdf5Reader h5(path);
  for (const char* name : {"/f", "/c_q", "/rms", "/t_c"})
    if (!h5.exists(name)) fail(std::string("no ") + name + ": not a result of `rover surface`");
  if (!same_axis(h5.read_doubles("/f"), f) || !same_axis(h5.read_doubles("/c_q"), c_q))
    fail("its grid (/f, /c_q) differs from the study's \"f\" and \"c_q\" axes");
  if (h5.has_attribute("/", "runs_key") && h5.attribute_string("/", "runs_key") != runs_key)
    fail("its runs were made against another reference (file or time_offset), scenario, rover or terrain than "
         "this study's (its runs_key " + h5.attribute_string("/", "runs_key") + ", this study's " + runs_key +
         "); make the grid with this study's \"reference\" and scenario");
  rms = h5.read_matrix("/rms");
  t_c = h5.read_matrix("/t_c");
  if (rms.rows() != static_cast<Eigen::Index>(f.size()) || rms.cols() != static_cast<Eigen::Index>(c_q.size()) ||
      t_c.rows() != rms.rows() || t_c.cols() != rms.cols())
    fail("/rms and /t_c are not nf x nc");
}

void write_surface_kriging(const SurfaceKriging& k, io::Hdf5Writer& h5) {
  h5.write("/gp/design/f", std::vector<double>(k.x.col(0).begin(), k.x.col(0).end()));
  h5.write("/gp/design/c_q", std::vector<double>(k.x.col(1).begin(), k.x.col(1).end()));
  h5.write("/gp/design/rms", std::vector<double>(k.rms.begin(), k.rms.end()));
  h5.write("/gp/design/t_c", std::vector<double>(k.t_c.begin(), k.t_c.end()));
  h5.write("/gp/design/status", k.status);
  h5.write("/gp/design/messages", k.messages);
  SurrogateSet set;
  set.kind = SurrogateKind::kGaussianProcess;
  for (const SurfaceKrigingMap& m : k.maps) {
    if (!m.fitted) continue;
    const std::string g = "/gp/" + m.name;
    h5.write(g + "/mean", m.mean);
    h5.write(g + "/sd", m.sd);
    h5.write(g + "/lower", m.lower);
    h5.write(g + "/upper", m.upper);
    h5.attribute(g, "log_scale", m.log_scale ? "true" : "false");
    h5.attribute(g, "nugget", m.model.gp.nugget);
    h5.attribute(g, "q2_loo", m.model.validation().q2_loo);
    if (m.checked) {
      h5.write(g + "/actual", m.actual);
      h5.write(g + "/error", m.error);
      h5.attribute(g, "q2", m.q2);
      h5.attribute(g, "max_abs_error", m.max_abs_error);
      h5.attribute(g, "coverage_3sd", m.coverage);
      h5.attribute(g, "check", k.check_source);
    }
    if (set.inputs.empty()) {
      set.inputs.push_back(surrogate_input("s_structure.f", "f", m.model.inputs[0], k.x.col(0)));
      set.inputs.push_back(surrogate_input("s_structure.c_q", "c_q", m.model.inputs[1], k.x.col(1)));
    }
    set.models.push_back(m.model);
  }
  if (!set.models.empty()) write_surrogate_set(h5, set);
}

// Below this nugget (a share of the process variance) a process
// interpolates its runs: its left-out error is the map's own.
constexpr double kInterpolatingNugget = 1e-6;

namespace {

// A process that interpolates its runs predicts them, left out one at a time, with a Q2 below the bar.
bool interpolates_badly(const SurfaceKrigingMap& m) {
  return m.fitted && m.model.gp.nugget < kInterpolatingNugget && !(m.model.gp.validation.q2_loo >= kDefaultQ2Threshold);
}

}  // namespace

bool surface_map_not_to_trust(const SurfaceKrigingMap& m) { return !m.wall_time && interpolates_badly(m); }

void report_surface_kriging(const SurfaceKriging& k, std::ostream& out) {
  const long ok = std::count(k.status.begin(), k.status.end(), run_status::kOk);
  out << "surface: kriging from " << ok << " of " << k.status.size() << " runs (Latin hypercube)\n";
  for (const SurfaceKrigingMap& m : k.maps) {
    if (!m.fitted) {
      out << "  " << m.name << ": no process: " << m.undefined_reason << "\n";
      continue;
    }
    const GaussianProcess& gp = m.model.gp;
    out << "  " << (m.log_scale ? "log " : "") << m.name << ": length-scales on F(x): f " << gp.length_scales(0)
        << " c_q " << gp.length_scales(1) << ", nugget " << gp.nugget << " (noise sd "
        << std::sqrt(gp.nugget * gp.process_variance) << (m.log_scale ? " in log units" : "") << "), Q2 LOO "
        << gp.validation.q2_loo << "\n";
    if (surface_map_not_to_trust(m))
      out << "  WARNING: " << m.name << "'s process predicts its own left-out runs with Q2 "
          << gp.validation.q2_loo << ", below " << kDefaultQ2Threshold
          << ": its map is not to be trusted between the runs (more runs, or a smaller range; exit status 2)\n";
    else if (interpolates_badly(m))
      out << "  note: " << m.name << " is a wall time and its process predicts its own left-out runs with Q2 "
          << gp.validation.q2_loo << ": its map shows the cost's trend at best, not a prediction\n";
    if (m.checked)
      out << "    against " << k.check_source << " (" << m.checked_points << " points): Q2 " << m.q2
          << ", largest error " << m.max_abs_error << ", " << m.covered_points << " of " << m.checked_points
          << " (" << 100.0 * m.coverage << " %) within " << kSurfaceCoverageSds << " predictive sd\n";
  }
}

}  // namespace rover::study
