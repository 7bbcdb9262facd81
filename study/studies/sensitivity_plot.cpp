// The sensitivity study's figures (sensitivity.hpp): the summary (S1 and ST
// per QoI, the indices along time per channel, or the Morris mu*-sigma plane
// per QoI), and with --plots all each of them on its own, with the
// intervals as bars and the output variance along time.
#include <algorithm>
#include <iostream>
#include <numeric>
#include <optional>

#include "io/plot.hpp"
#include "study/studies/report_format.hpp"
#include "study/studies/sensitivity.hpp"
#include "study/studies/study_output.hpp"
#include "study/studies/summary_figure.hpp"

namespace rover::study {
namespace {

// Room beside the largest Morris effects for their labels.
constexpr double kMorrisLabelRoomX = 1.3, kMorrisLabelRoomY = 1.15;

void plot_sobol(const std::string& png, const std::string& qoi, const SobolIndices& s,
                const std::vector<std::string>& labels, double confidence) {
  io::BarPlot plot;
  plot.title = qoi + ": Sobol' indices (" + std::to_string(s.groups_used) + " groups), " +
               percent_digits(confidence) + " % intervals";
  plot.y_label = "index";
  plot.categories = labels;
  plot.groups.push_back({"S1 (first order)", to_vector(s.S1), to_vector(s.S1_lower), to_vector(s.S1_upper)});
  plot.groups.push_back({"ST (total)", to_vector(s.ST), to_vector(s.ST_lower), to_vector(s.ST_upper)});
  io::write_png_or_warn(plot, png, "sensitivity", std::cerr);
}

// S_i(t) of the inputs that matter; nullopt when none does.
std::optional<io::LinePlot> indices_along_time(const std::string& channel, const SobolIndicesAlongTime& s,
                                               const std::vector<double>& t, const std::vector<std::string>& labels) {
  io::LinePlot indices;
  indices.title = channel + ": first-order (solid) and total (dashed) Sobol' indices along time";
  indices.x_label = "t [s]";
  indices.y_label = "index";
  indices.y_range = io::AxisRange{-0.05, 1.05};
  for (Eigen::Index i = 0; i < s.S1.rows(); ++i) {
    if (!(s.aggregated_ST[i] > kPlottedTotalIndex)) continue;
    const std::string& name = labels[static_cast<std::size_t>(i)];
    std::vector<double> s1, st;
    for (Eigen::Index k = 0; k < s.S1.cols(); ++k) {
      s1.push_back(s.S1(i, k));
      st.push_back(s.ST(i, k));
    }
    indices.series.push_back({name + " S1", t, s1});
    indices.series.push_back({name + " ST", t, st, io::SeriesStyle::dashed});
  }
  if (indices.series.empty()) return std::nullopt;
  return indices;
}

// The output variance V(t) under the indices.
io::LinePlot variance_along_time(const std::string& channel, const SobolIndicesAlongTime& s,
                                 const std::vector<double>& t) {
  io::LinePlot variance;
  variance.title = channel + ": output variance along time";
  variance.x_label = "t [s]";
  variance.y_label = "Var " + channel;
  variance.series.push_back({"V(t)", t, to_vector(s.variance)});
  return variance;
}

// S1 and ST of every input (numbered on the x axis, named at ST), with the
// interval of ST when there is one.
io::LinePlot indices_panel(const std::string& title, const std::vector<std::string>& labels,
                           const Eigen::VectorXd& S1, const Eigen::VectorXd& ST, const Eigen::VectorXd* ST_lower,
                           const Eigen::VectorXd* ST_upper) {
  io::LinePlot p;
  p.title = title;
  p.x_label = "input";
  p.y_label = "index";
  p.x_range = io::AxisRange{0.5, static_cast<double>(labels.size()) + 0.5};
  std::vector<double> x(labels.size());
  std::iota(x.begin(), x.end(), 1.0);
  p.series.push_back({"S1", x, to_vector(S1), io::SeriesStyle::points});
  p.series.push_back({"ST", x, to_vector(ST), io::SeriesStyle::points});
  if (ST_lower != nullptr && ST_upper != nullptr && ST_lower->size() == ST.size())
    p.bands.push_back({"ST interval", x, to_vector(*ST_lower), to_vector(*ST_upper)});
  for (std::size_t i = 0; i < labels.size(); ++i)
    p.labels.push_back({x[i], ST[static_cast<Eigen::Index>(i)], labels[i]});
  return p;
}

io::LinePlot morris_plane(const std::string& qoi, const MorrisResult& m, const std::vector<std::string>& labels) {
  io::LinePlot plot;
  plot.title = qoi + ": Morris screening (" + std::to_string(m.trajectories_used) + " trajectories)";
  plot.x_label = "mu* (mean |elementary effect|)";
  plot.y_label = "sigma (sd of the elementary effects)";
  io::Series points{"inputs"};
  points.style = io::SeriesStyle::points;
  for (Eigen::Index i = 0; i < m.mu_star.size(); ++i) {
    points.x.push_back(m.mu_star[i]);
    points.y.push_back(m.sigma[i]);
    plot.labels.push_back({m.mu_star[i], m.sigma[i], labels[static_cast<std::size_t>(i)]});
  }
  plot.series.push_back(points);
  // Room for the labels of the largest effects.
  plot.x_range = io::AxisRange{0.0, kMorrisLabelRoomX * m.mu_star.maxCoeff()};
  plot.y_range = io::AxisRange{0.0, kMorrisLabelRoomY * std::max(m.sigma.maxCoeff(), m.mu_star.maxCoeff())};
  plot.series.push_back({"sigma = mu*", {0.0, m.mu_star.maxCoeff()}, {0.0, m.mu_star.maxCoeff()}, io::SeriesStyle::dashed});
  return plot;
}

std::vector<io::LinePlot> summary_panels(const SensitivityResult& result) {
  const SensitivityStudy& study = result.study;
  const StudyModel& model = *study.spec.model;
  const std::vector<std::string> labels = input_labels(study.spec);
  std::vector<io::LinePlot> panels;
  for (std::size_t q = 0; q < result.sobol.size(); ++q) {
    const SobolIndices& s = result.sobol[q];
    if (s.S1.size() == 0) continue;  // undefined
    panels.push_back(indices_panel(model.qoi_names()[q] + ": Sobol' S1 and ST", labels, s.S1, s.ST, &s.ST_lower,
                                   &s.ST_upper));
  }
  for (const PceQoiResult& q : result.pce.qoi) {
    if (!q.indices.defined) continue;
    const bool intervals = q.has_intervals;
    panels.push_back(indices_panel(q.name + ": PCE S1 and ST", labels, q.indices.S1, q.indices.ST,
                                   intervals ? &q.intervals.ST_lower : nullptr,
                                   intervals ? &q.intervals.ST_upper : nullptr));
  }
  for (std::size_t c = 0; c < result.sobol_t.size(); ++c)
    if (auto p = indices_along_time(model.channel_names()[c], result.sobol_t[c], model.time_s(), labels))
      panels.push_back(std::move(*p));
  for (std::size_t q = 0; q < result.morris.size(); ++q)
    if (result.morris[q].mu_star.size() != 0)
      panels.push_back(morris_plane(model.qoi_names()[q], result.morris[q], labels));
  return panels;
}

}  // namespace

namespace {

// The file names of the figures, shared by plot_sensitivity and sensitivity_figures.
std::string sobol_suffix(const std::string& qoi) { return "_sobol_" + qoi + ".png"; }
std::string sobol_t_suffix(const std::string& channel) { return "_sobol_t_" + channel + ".png"; }
std::string sobol_variance_suffix(const std::string& channel) { return "_sobol_t_" + channel + "_variance.png"; }
std::string morris_suffix(const std::string& qoi) { return "_morris_" + qoi + ".png"; }

}  // namespace

std::vector<PlannedFigure> sensitivity_figures(const SensitivityStudy& study, PlotSelection plots) {
  std::vector<PlannedFigure> figures = summary_figure(plots);
  if (plots != PlotSelection::kAll) return figures;
  const StudyModel& model = *study.spec.model;
  if (study.method == SensitivityMethod::kPce) return pce_sensitivity_figures(study.spec, figures);
  for (const std::string& q : model.qoi_names())
    if (study.method == SensitivityMethod::kSobol) figures.push_back({sobol_suffix(q), "QoI '" + q + "'"});
    else figures.push_back({morris_suffix(q), "QoI '" + q + "'"});
  if (study.method != SensitivityMethod::kSobol) return figures;
  for (const std::string& c : model.channel_names()) {
    figures.push_back({sobol_t_suffix(c), "channel '" + c + "' (its indices along time)"});
    figures.push_back({sobol_variance_suffix(c), "channel '" + c + "' (its variance along time)"});
  }
  return figures;
}

void plot_sensitivity(const SensitivityResult& result, const std::string& results_path, PlotSelection plots) {
  if (plots == PlotSelection::kNone) return;
  const SensitivityStudy& study = result.study;
  const StudyModel& model = *study.spec.model;
  const std::vector<std::string> labels = input_labels(study.spec);
  auto png = [&](const std::string& suffix) { return sibling_path(results_path, suffix); };
  write_summary_figure(study.spec.name + ": " + sensitivity_method_name(study.method) + ", " +
                           std::to_string(result.status.size()) + " runs",
                       summary_panels(result), png("_summary.png"), "sensitivity");
  if (plots != PlotSelection::kAll) return;
  if (study.method == SensitivityMethod::kPce) plot_pce_sensitivity(results_path, study.spec, result.pce);
  for (std::size_t q = 0; q < result.sobol.size(); ++q)
    if (result.sobol[q].S1.size() != 0)
      plot_sobol(png(sobol_suffix(model.qoi_names()[q])), model.qoi_names()[q], result.sobol[q], labels,
                 study.sobol.confidence);
  for (std::size_t c = 0; c < result.sobol_t.size(); ++c) {
    const std::string& channel = model.channel_names()[c];
    if (const auto p = indices_along_time(channel, result.sobol_t[c], model.time_s(), labels))
      io::write_png_or_warn(*p, png(sobol_t_suffix(channel)), "sensitivity", std::cerr);
    io::write_png_or_warn(variance_along_time(channel, result.sobol_t[c], model.time_s()),
                          png(sobol_variance_suffix(channel)), "sensitivity", std::cerr);
  }
  for (std::size_t q = 0; q < result.morris.size(); ++q)
    if (result.morris[q].mu_star.size() != 0)
      io::write_png_or_warn(morris_plane(model.qoi_names()[q], result.morris[q], labels),
                            png(morris_suffix(model.qoi_names()[q])), "sensitivity", std::cerr);
}

}  // namespace rover::study
