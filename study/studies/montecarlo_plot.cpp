// The Monte Carlo study's figures (montecarlo.hpp): the summary (the band of
// each channel, the histogram and running mean of each QoI), and with
// --plots all each of them on its own and the running sd.
#include <algorithm>
#include <iostream>

#include "io/plot.hpp"
#include "study/studies/montecarlo.hpp"
#include "study/studies/report_format.hpp"
#include "study/studies/study_output.hpp"
#include "study/studies/summary_figure.hpp"

namespace rover::study {
namespace {

std::vector<double> scaled(const std::vector<double>& v, double factor) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [&](double x) { return factor * x; });
  return out;
}

io::LinePlot band_plot(const std::string& title, const std::string& channel, const std::string& unit,
                       const std::vector<double>& t, const Band& band) {
  const DisplayUnit shown = display_unit(unit);
  io::LinePlot plot;
  plot.x_label = "t [s]";
  plot.y_label = channel + " [" + shown.name + "]";
  if (band.samples_used < 2) {  // one curve: no spread to show
    plot.title = title + ": " + channel + ", " + std::to_string(band.samples_used) + " run (no band)";
    plot.series.push_back({"the one run", t, scaled(band.mean, shown.factor)});
    return plot;
  }
  plot.title = title + ": " + channel + ", " + std::to_string(band.samples_used) + " runs";
  plot.bands.push_back({"mean -+ 3 sd", t, scaled(band.lower, shown.factor), scaled(band.upper, shown.factor)});
  plot.series.push_back({"mean", t, scaled(band.mean, shown.factor)});
  plot.series.push_back({"0.135 % quantile", t, scaled(band.p00135, shown.factor), io::SeriesStyle::dashed});
  plot.series.push_back({"99.865 % quantile", t, scaled(band.p99865, shown.factor), io::SeriesStyle::dashed});
  return plot;
}

// The summary: each channel's band, then each QoI's histogram and running
// mean.
std::vector<io::LinePlot> summary_panels(const MonteCarloResult& result) {
  const StudySpec& spec = result.study.spec;
  const StudyModel& model = *spec.model;
  const double confidence = result.study.confidence;
  std::vector<io::LinePlot> panels;
  for (std::size_t c = 0; c < result.bands.size(); ++c) {
    const std::string& name = model.channel_names()[c];
    panels.push_back(band_plot(spec.name, name, channel_unit(channel_from_name(name)), model.time_s(), result.bands[c]));
  }
  for (std::size_t q = 0; q < result.qoi.size(); ++q) {
    const std::string& name = model.qoi_names()[q];
    const std::string& unit = model.qoi_units()[q];
    if (auto h = histogram_panel(name, unit, result.qoi[q], &result.summaries[q], confidence))
      panels.push_back(std::move(*h));
    if (auto c = convergence_panels(name, unit, result.qoi[q], confidence)) panels.push_back(std::move(c->mean));
  }
  return panels;
}

}  // namespace

namespace {

// The file names of the figures, shared by plot_montecarlo and montecarlo_figures.
std::string band_suffix(const std::string& channel) { return "_band_" + channel + ".png"; }
std::string hist_suffix(const std::string& qoi) { return "_hist_" + qoi + ".png"; }
std::string convergence_suffix(const std::string& qoi, const char* moment) {
  return "_convergence_" + qoi + "_" + moment + ".png";
}

}  // namespace

std::vector<PlannedFigure> montecarlo_figures(const MonteCarloStudy& study, PlotSelection plots) {
  std::vector<PlannedFigure> figures = summary_figure(plots);
  if (plots != PlotSelection::kAll) return figures;
  const StudyModel& model = *study.spec.model;
  for (const std::string& c : model.channel_names()) figures.push_back({band_suffix(c), "channel '" + c + "'"});
  for (const std::string& q : model.qoi_names()) {
    figures.push_back({hist_suffix(q), "QoI '" + q + "' (histogram)"});
    for (const char* moment : {"mean", "sd"})
      figures.push_back({convergence_suffix(q, moment), "QoI '" + q + "' (running " + moment + ")"});
  }
  return figures;
}

void plot_montecarlo(const MonteCarloResult& result, const std::string& results_path, PlotSelection plots) {
  if (plots == PlotSelection::kNone) return;
  const StudySpec& spec = result.study.spec;
  const StudyModel& model = *spec.model;
  const double confidence = result.study.confidence;
  auto png = [&](const std::string& suffix) { return sibling_path(results_path, suffix); };
  write_summary_figure(spec.name + ": " + std::to_string(result.samples) + " runs (" +
                           std::to_string(result.failed) + " failed)",
                       summary_panels(result), png("_summary.png"), "montecarlo");
  if (plots != PlotSelection::kAll) return;
  for (std::size_t c = 0; c < result.bands.size(); ++c) {
    const std::string& name = model.channel_names()[c];
    io::write_png_or_warn(band_plot(spec.name, name, channel_unit(channel_from_name(name)), model.time_s(),
                                    result.bands[c]),
                          png(band_suffix(name)), "montecarlo", std::cerr);
  }
  for (std::size_t q = 0; q < result.qoi.size(); ++q) {
    const std::string& name = model.qoi_names()[q];
    const std::string& unit = model.qoi_units()[q];
    if (const auto h = histogram_panel(name, unit, result.qoi[q], &result.summaries[q], confidence))
      io::write_png_or_warn(*h, png(hist_suffix(name)), "montecarlo", std::cerr);
    if (const auto c = convergence_panels(name, unit, result.qoi[q], confidence)) {
      io::write_png_or_warn(c->mean, png(convergence_suffix(name, "mean")), "montecarlo", std::cerr);
      io::write_png_or_warn(c->sd, png(convergence_suffix(name, "sd")), "montecarlo", std::cerr);
    }
  }
}

}  // namespace rover::study
