// The surface study's figures (surface.hpp): the summary (the RMS error and
// t_c over f, one line per c_q, and the sweep of t_c over f with its
// regression), and with --plots all heat maps of the RMS error and of t_c
// over (f, c_q) and the sweep on its own. A kriged surface (surface_kriging.hpp)
// shows the predicted RMS error and t_c, and their predictive sd, in place of
// the grid's runs.
#include <cmath>
#include <iostream>

#include "core/number_text.hpp"
#include "io/plot.hpp"
#include "study/studies/report_format.hpp"
#include "study/studies/study_output.hpp"
#include "study/studies/summary_figure.hpp"
#include "study/studies/surface.hpp"

namespace rover::study {
namespace {

io::SurfacePlot heat_map(const SurfaceResult& r, const Eigen::MatrixXd& z, double scale, const std::string& label) {
  io::SurfacePlot p;
  p.title = r.study.name + ": " + label + " (" + integrator_name(r.integrator.method) + ")";
  p.x_label = "f [1/rad]";
  p.y_label = "c_q [N m s/rad]";
  p.z_label = label;
  p.x = r.study.f;
  p.y = r.study.c_q;
  p.log_x = true;
  for (Eigen::Index j = 0; j < z.cols(); ++j)
    for (Eigen::Index i = 0; i < z.rows(); ++i) p.z.push_back(scale * z(i, j));
  return p;
}

io::LinePlot sweep_plot(const SurfaceResult& r) {
  io::LinePlot p;
  p.title = r.study.name + ": t_c over f (" + integrator_name(r.integrator.method) + ")";
  p.x_label = "f [1/rad]";
  p.y_label = "t_c [s]";
  io::Series points{"runs", r.study.sweep_f, r.sweep_t_c, io::SeriesStyle::points};
  const std::string r_squared =
      std::isnan(r.regression.r_squared) ? "none: under 3 timed runs" : number_text(r.regression.r_squared);
  io::Series fit{"t_c = a + b f (r^2 " + r_squared + ")"};
  for (double f : r.study.sweep_f) {
    fit.x.push_back(f);
    fit.y.push_back(r.regression.intercept + r.regression.slope * f);
  }
  p.series = {points, fit};
  return p;
}

// z(f) for every c_q of the grid.
io::LinePlot lines_over_f(const SurfaceResult& r, const Eigen::MatrixXd& z, double scale, const std::string& label) {
  io::LinePlot p;
  p.title = r.study.name + ": " + label;
  p.x_label = "f [1/rad]";
  p.y_label = label;
  p.log_x = true;
  for (Eigen::Index j = 0; j < z.cols(); ++j) {
    io::Series line{"c_q = " + number_text(r.study.c_q[static_cast<std::size_t>(j)]), r.study.f, {},
                    io::SeriesStyle::lines_points};
    for (Eigen::Index i = 0; i < z.rows(); ++i) line.y.push_back(scale * z(i, j));
    p.series.push_back(std::move(line));
  }
  return p;
}

// The kriged maps: mean and predictive sd of the RMS error and t_c.
std::vector<io::LinePlot> kriging_panels(const SurfaceResult& r) {
  std::vector<io::LinePlot> panels;
  const DisplayUnit mm = display_unit("m");
  for (const SurfaceKrigingMap& m : r.kriging.maps) {
    if (!m.fitted) continue;
    const bool rms = m.name == "rms";
    const double scale = rms ? mm.factor : 1.0;
    const std::string label = rms ? "RMS of B_l z [" + mm.name + "]" : "t_c [s]";
    panels.push_back(lines_over_f(r, m.mean, scale, "kriged " + label));
    panels.push_back(lines_over_f(r, m.sd, scale, "predictive sd of " + label));
  }
  return panels;
}

std::vector<io::LinePlot> summary_panels(const SurfaceResult& r) {
  if (r.study.kriging.enabled) return kriging_panels(r);
  std::vector<io::LinePlot> panels;
  const DisplayUnit mm = display_unit("m");
  panels.push_back(lines_over_f(r, r.rms, mm.factor, "RMS of B_l z [" + mm.name + "]"));
  panels.push_back(lines_over_f(r, r.t_c, 1.0, "t_c [s]"));
  if (r.study.sweep_f.size() > 1) panels.push_back(sweep_plot(r));
  return panels;
}

}  // namespace

std::vector<PlannedFigure> surface_figures(const SurfaceStudy& study, PlotSelection plots) {
  std::vector<PlannedFigure> figures = summary_figure(plots);
  if (plots != PlotSelection::kAll) return figures;
  if (study.runs_grid()) {
    figures.push_back({"_rms.png", "the RMS error over (f, c_q)"});
    figures.push_back({"_tc.png", "t_c over (f, c_q)"});
  }
  if (study.sweep_f.size() > 1) figures.push_back({"_sweep.png", "the sweep over f"});
  return figures;
}

void plot_surface(const SurfaceResult& r, const std::string& results_path, PlotSelection plots) {
  if (plots == PlotSelection::kNone) return;
  auto png = [&](const std::string& suffix) { return sibling_path(results_path, suffix); };
  write_summary_figure(r.study.name + " (" + integrator_name(r.integrator.method) + "): " +
                           std::to_string(r.runs) + " runs (" + std::to_string(r.failed) + " failed)",
                       summary_panels(r), png("_summary.png"), "surface");
  if (plots != PlotSelection::kAll) return;
  try {
    if (r.rms.rows() > 1 && r.rms.cols() > 1 && r.study.runs_grid()) {
      const DisplayUnit mm = display_unit("m");
      io::write_png(heat_map(r, r.rms, mm.factor, "RMS of B_l z [" + mm.name + "]"), png("_rms.png"));
      std::cerr << "surface: wrote " << png("_rms.png") << "\n";
      io::write_png(heat_map(r, r.t_c, 1.0, "t_c [s]"), png("_tc.png"));
      std::cerr << "surface: wrote " << png("_tc.png") << "\n";
    }
    if (r.study.sweep_f.size() > 1) {
      io::write_png(sweep_plot(r), png("_sweep.png"));
      std::cerr << "surface: wrote " << png("_sweep.png") << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "surface: warning: no plot (" << e.what() << ")\n";
  }
}

}  // namespace rover::study
