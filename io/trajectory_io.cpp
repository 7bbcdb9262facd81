// See trajectory_io.hpp.
#include "io/trajectory_io.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/coordinates.hpp"
#include "core/friction_synthesis.hpp"
#include "core/model_scale.hpp"
#include "core/number_text.hpp"
#include "io/csv.hpp"
#include "io/hdf5_file.hpp"
#include "io/plot.hpp"

namespace rover::io {
namespace {

std::string file_text(const std::string& path) {
  if (path.empty()) return "";
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A record that `rover simulate` wrote of a failed run (status_code not 0):
// its curve stops, or runs away, where the run failed, so no reader may take
// it for a trajectory. Files without the attribute (other tools) pass.
void refuse_failed_run_record(const Hdf5Reader& h5, const std::string& path) {
  if (!h5.has_attribute("/", "status_code") || h5.attribute_integer("/", "status_code") == 0) return;
  const std::string status = h5.has_attribute("/", "status") ? h5.attribute_string("/", "status") : "failed";
  const std::string message = h5.has_attribute("/", "message") ? h5.attribute_string("/", "message") : "";
  throw ConfigError(path + ": the record of a failed run (status '" + status + "'" +
                    (message.empty() ? "" : ": " + message) +
                    "), not a trajectory; give the file of a run that succeeded");
}

// The attributes of a trajectory file: the inputs, the integrator and the run's outcome.
void write_run_attributes(Hdf5Writer& h5, const Trajectory& tr, const ScenarioSetup& setup,
                          const ModelInputs& inputs) {
  const Scenario& s = setup.scenario;
  const IntegratorSettings& integ = s.integrator;
  h5.attribute("/", "project_version", ROVER_VERSION);
  h5.attribute("/", "scenario", s.name);
  h5.attribute("/", "scenario_file", setup.scenario_path);
  h5.attribute("/", "rover_file", setup.rover_path);
  h5.attribute("/", "terrain_file", setup.terrain_path.empty() ? "flat z = 0" : setup.terrain_path);
  h5.attribute("/", "scenario_json", file_text(setup.scenario_path));
  h5.attribute("/", "rover_json", file_text(setup.rover_path));
  h5.attribute("/", "f", inputs.sharpness_f);
  h5.attribute("/", "c_q", inputs.damping_c_q);
  h5.attribute("/", "M0", std::vector<double>(inputs.preload_Nm.begin(), inputs.preload_Nm.end()));
  const auto& g = setup.model.parameters.friction.gammas;
  h5.attribute("/", "friction_gammas", std::vector<double>(g.begin(), g.end()));
  const FrictionFitQuality fit = friction_fit_quality(g, setup.model.parameters.friction);
  h5.attribute("/", "friction_fit_rms", fit.rms);
  h5.attribute("/", "friction_fit_peak_mu", fit.peak_mu);
  h5.attribute("/", "friction_fit_acceptable", static_cast<long long>(fit.acceptable ? 1 : 0));
  h5.attribute("/", "duration_s", s.duration_s);
  h5.attribute("/", "output_rate_hz", s.output_rate_hz);
  h5.attribute("/", "integrator", integrator_name(integ.method));
  h5.attribute("/", "rtol", integ.relative_tolerance);
  h5.attribute("/", "atol", integ.absolute_tolerance);
  h5.attribute("/", "slip_tol", integ.slip_tolerance);
  h5.attribute("/", "initial_step_s", integ.initial_step_s);
  h5.attribute("/", "min_step_s", integ.min_step_s);
  h5.attribute("/", "max_step_s", integ.max_step_s);
  h5.attribute("/", "fixed_step_s", integ.fixed_step_s);
  h5.attribute("/", "status", status_name(tr.status));
  h5.attribute("/", "status_code", static_cast<long long>(tr.status));
  h5.attribute("/", "message", tr.message);
  h5.attribute("/", "wall_time_s", tr.wall_time_s);
  h5.attribute("/", "rhs_evaluations", static_cast<long long>(tr.rhs_evaluations));
  h5.attribute("/", "steps", static_cast<long long>(tr.steps));
  h5.attribute("/", "smallest_step_s", tr.min_step_s);
  h5.attribute("/", "largest_step_s", tr.max_step_s);
}

bool stopped(const std::atomic<bool>* stop) { return stop != nullptr && stop->load(); }

}  // namespace

bool write_trajectory_hdf5(const std::string& path, const Trajectory& tr, const ScenarioSetup& setup,
                           const ModelInputs& inputs, const std::atomic<bool>* stop) {
  Hdf5Writer h5(path);  // destroyed uncommitted on a stop: its temporary goes
  const std::pair<const char*, const std::vector<double>*> curves[] = {
      {"/t", &tr.t}, {"/B_l_z", &tr.B_l_z}, {"/B_r_z", &tr.B_r_z}, {"/G_z", &tr.G_z}, {"/pitch", &tr.pitch},
      {"/roll", &tr.roll}};
  for (const auto& [name, values] : curves) {
    if (stopped(stop)) return false;
    h5.write(name, *values);
  }
  const std::pair<const char*, const RowMatrix*> matrices[] = {{"/q", &tr.q}, {"/u", &tr.u}, {"/Fn", &tr.normal_force_N}};
  for (const auto& [name, values] : matrices) {
    if (stopped(stop)) return false;
    h5.write(name, Eigen::MatrixXd(*values));
  }
  std::vector<std::string> names(std::begin(kCoordinateNames), std::end(kCoordinateNames));
  h5.write("/coordinate_names", names);
  write_run_attributes(h5, tr, setup, inputs);
  if (stopped(stop)) return false;
  h5.commit();
  return true;
}

bool write_trajectory_csv(const std::string& path, const Trajectory& tr, const std::atomic<bool>* stop) {
  std::vector<std::string> header{"t", "B_l_z", "B_r_z", "G_z", "pitch", "roll"};
  std::vector<std::vector<double>> columns{tr.t, tr.B_l_z, tr.B_r_z, tr.G_z, tr.pitch, tr.roll};
  auto add_matrix = [&](const RowMatrix& m, const std::string& prefix, auto name_of) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) {
      header.push_back(prefix + name_of(static_cast<int>(c)));
      columns.emplace_back(m.rows());
      for (Eigen::Index r = 0; r < m.rows(); ++r) columns.back()[static_cast<std::size_t>(r)] = m(r, c);
    }
  };
  add_matrix(tr.q, "q_", [](int c) { return std::string(kCoordinateNames[c]); });
  add_matrix(tr.u, "u_", [](int c) { return std::string(kCoordinateNames[c]); });
  add_matrix(tr.normal_force_N, "Fn_", [](int c) { return std::to_string(c + 1); });
  return write_csv(path, header, columns, "", stop);
}

std::vector<std::string> write_trajectory_plots(const std::string& png_stem, const Trajectory& tr,
                                                const std::string& title, bool obstacle_run,
                                                const std::atomic<bool>* stop) {
  std::vector<std::string> written;
  auto mm = [](const std::vector<double>& z) {
    std::vector<double> out(z.size());
    for (std::size_t i = 0; i < z.size(); ++i) out[i] = 1000.0 * z[i];
    return out;
  };
  auto series = [](std::string label, const std::vector<double>& x, std::vector<double> y) {
    Series s;
    s.label = std::move(label);
    s.x = x;
    s.y = std::move(y);
    return s;
  };
  LinePlot heights;
  heights.title = title;
  heights.x_label = "t [s]";
  heights.y_label = "z [mm]";
  heights.series.push_back(series("B_l z", tr.t, mm(tr.B_l_z)));
  if (obstacle_run) {
    heights.series.push_back(series("B_r z", tr.t, mm(tr.B_r_z)));
    heights.series.push_back(series("G z", tr.t, mm(tr.G_z)));
  }
  if (stopped(stop)) return written;
  write_png(heights, png_stem + ".png");
  written.push_back(png_stem + ".png");
  if (obstacle_run && !stopped(stop)) {
    LinePlot attitude;
    attitude.title = title + ": attitude";
    attitude.x_label = "t [s]";
    attitude.y_label = "angle [deg]";
    auto deg = [](const std::vector<double>& a) {
      std::vector<double> out(a.size());
      for (std::size_t i = 0; i < a.size(); ++i) out[i] = a[i] * 180.0 / std::numbers::pi;
      return out;
    };
    attitude.series.push_back(series("pitch chi", tr.t, deg(tr.pitch)));
    attitude.series.push_back(series("roll psi", tr.t, deg(tr.roll)));
    write_png(attitude, png_stem + "_attitude.png");
    written.push_back(png_stem + "_attitude.png");
  }
  return written;
}

namespace {

// The largest |value| a simulated curve of `column` can hold: a height
// (B_l_z, G_z, ...) stays within the positions the model simulates; other
// channels are not bounded here.
double simulated_curve_bound(const std::string& column) {
  return column.ends_with("_z") ? kMaxCoordinate_m : std::numeric_limits<double>::infinity();
}

}  // namespace

Curve read_curve(const std::string& path, const std::string& column) {
  if (const std::string problem = input_path_problem(path, "a curve file (CSV or HDF5)"); !problem.empty())
    throw ConfigError(path + ": " + problem);
  Curve c;
  if (ends_with(path, ".csv")) {
    // Simulated trajectories have the column; measured drop data has t,z
    // and goes through the measured-curve checks.
    const CsvTable table = read_csv(path, {"t"});
    const auto& h = table.header;
    MeasuredCurve curve;
    if (std::find(h.begin(), h.end(), column) != h.end()) {
      curve = curve_from_table(table, column, simulated_curve_bound(column));
    } else {
      if (std::find(h.begin(), h.end(), "z") == h.end())
        throw ConfigError(path + ": no column '" + column + "', nor 'z' of measured data");
      if (const std::string declared = declared_channel(path); !declared.empty() && declared != column)
        throw ConfigError(path + ": declares its z to be " + declared + " (its header), but is read as " + column +
                          ": give a curve of " + column);
      curve = curve_from_table(table, "z", kMeasuredCurveMaxAbsHeight_m);
    }
    c.t = std::move(curve.t_s);
    c.y = std::move(curve.z_m);
    return c;
  }
  const Hdf5Reader h5(path);
  refuse_failed_run_record(h5, path);
  if (!h5.exists("/" + column)) {
    std::string names;
    for (const std::string& name : h5.list("/")) names += (names.empty() ? "" : ", ") + name;
    throw ConfigError(path + ": no column '" + column + "' (the file holds: " + names + ")");
  }
  c.t = h5.read_doubles("/t");
  c.y = h5.read_doubles("/" + column);
  const auto refuse = [&](const auto&... parts) {
    std::ostringstream message;
    message << path << ": ";
    (message << ... << parts);
    throw ConfigError(message.str());
  };
  if (c.t.size() != c.y.size())
    refuse("/t has ", c.t.size(), " values, /", column, " has ", c.y.size());
  if (c.t.size() < kMeasuredCurveMinRows)
    refuse("/t has ", c.t.size(), " sample(s); a curve needs at least ", kMeasuredCurveMinRows);
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    if (!std::isfinite(c.t[i]) || !std::isfinite(c.y[i]))
      refuse("sample ", i, ": t = ", c.t[i], ", ", column, " = ", c.y[i], " is not finite");
    if (!(std::abs(c.y[i]) < simulated_curve_bound(column)))
      refuse("sample ", i, ": ", column, " = ", number_text(c.y[i]), " m is beyond the bound |", column, "| < ",
             number_text(simulated_curve_bound(column)), " m of any simulated height (a damaged file?)");
    if (i > 0 && !(c.t[i] > c.t[i - 1]))
      refuse("/t[", i, "] = ", c.t[i], " does not follow /t[", i - 1, "] = ", c.t[i - 1],
             "; times must increase strictly");
  }
  return c;
}

}  // namespace rover::io
