// The figures of a calibration posterior (calibration_mcmc.hpp): the trace
// of every parameter, the corner plot of the samples and the posterior
// predictive band of each curve.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>

#include <boost/histogram.hpp>

#include "io/plot.hpp"
#include "study/studies/calibration_mcmc.hpp"
#include "study/studies/report_number.hpp"
#include "study/studies/report_format.hpp"

namespace rover::study {
namespace {

// A sampled parameter as the corner plot shows it: its name and unit
// (study/studies/calibration.hpp), the noise sd in mm rather than metres.
struct CornerParameter {
  std::string label{};  // axis label, with unit
  double scale = 1.0;   // shown value = scale * sampled value
};
CornerParameter corner_parameter(const std::string& name) {
  if (name == "c_q") return {"c_q [N m s/rad]"};
  if (name == "f") return {"f [1/rad]"};
  if (name == "time_offset") return {"time_offset [s]"};
  if (name.starts_with("noise_sd")) return {name + " [mm]", 1e3};
  return {name};  // M0_scale, a factor
}

constexpr int kCornerMaxTicks = 5;

// One parameter's marginal: the histogram of its kept samples (shown units),
// its mean (solid) and 95 % interval (dashed); `range` receives the
// histogram's edges.
io::LinePlot marginal_panel(const CornerParameter& parameter, const Eigen::MatrixXd& tail, double mean, double q025,
                            double q975, io::AxisRange& range) {
  double lo = tail.minCoeff(), hi = tail.maxCoeff();
  if (!(hi > lo)) {  // one value (a stuck chain): a bin around it
    const double half = std::max(1e-12, 1e-3 * std::abs(lo));
    lo -= half;
    hi += half;
  }
  range = {lo, hi};
  const int bins = std::clamp(static_cast<int>(std::lround(std::sqrt(static_cast<double>(tail.size())))), 5, 40);
  // The top edge nudged up so that the largest sample falls in the last bin, not the overflow.
  auto histogram = boost::histogram::make_histogram(
      boost::histogram::axis::regular<double>(static_cast<unsigned>(bins), lo, std::nextafter(hi, hi + 1.0)));
  for (Eigen::Index j = 0; j < tail.size(); ++j) histogram(tail.data()[j]);
  io::Band filled{.color = "#4060a0", .opacity = 0.3};
  io::Series outline{.color = "#4060a0", .line_width = 1.2};
  double highest = 0.0;
  for (int b = 0; b < bins; ++b) {
    const auto bin = histogram.axis().bin(b);
    const double count = histogram.at(b);
    highest = std::max(highest, count);
    for (const double edge : {bin.lower(), bin.upper()}) {
      filled.x.push_back(edge);
      filled.lower.push_back(0.0);
      filled.upper.push_back(count);
      outline.x.push_back(edge);
      outline.y.push_back(count);
    }
  }
  const double top = 1.1 * std::max(highest, 1.0);
  const double gap = std::numeric_limits<double>::quiet_NaN();
  io::LinePlot panel{.title = "mean " + format_number(mean) + ", 95 % [" + format_number(q025) + ", " +
                              format_number(q975) + "]",
                     .x_label = parameter.label,
                     .y_label = "samples per bin",
                     .x_range = range,
                     .y_range = io::AxisRange{0.0, top},
                     .max_ticks = kCornerMaxTicks};
  panel.bands.push_back(std::move(filled));
  panel.series.push_back(std::move(outline));
  panel.series.push_back({.x = {mean, mean}, .y = {0.0, top}, .color = "dark-red"});
  panel.series.push_back({.x = {q025, q025, gap, q975, q975},
                          .y = {0.0, top, gap, 0.0, top},
                          .style = io::SeriesStyle::dashed,
                          .color = "dark-red"});
  return panel;
}

// The corner plot (Foreman-Mackey 2016) of the samples after `discard`
// burn-in steps, p x p panels for p parameters (samples[k]: steps x chains):
// on the diagonal the marginal histogram of parameter k over all kept samples
// (square-root choice of the bin count, 5 to 40 bins) with the posterior
// mean (solid line) and 95 % interval (dashed), also in the panel's title;
// below it the scatter of parameter (column) against parameter (row) over at
// most 2000 samples spread evenly over the kept steps and chains; blank
// above. The panels of a column share the x range of its histogram, those of
// a row the range of its parameter, so one parameter's axes line up.
io::PanelGrid corner_plot(const std::string& title, const std::vector<CornerParameter>& parameters,
                          const std::vector<Eigen::MatrixXd>& samples, long discard, const std::vector<double>& mean,
                          const std::vector<double>& q025, const std::vector<double>& q975) {
  constexpr long kMaxScatterPoints = 2000;
  const int p = static_cast<int>(parameters.size());
  const long steps = samples.front().rows(), chains = samples.front().cols(), kept = steps - discard;
  std::vector<io::AxisRange> range(static_cast<std::size_t>(p));  // the histogram's edges, shown units
  io::PanelGrid grid{.title = title, .rows = p, .cols = p};
  grid.panels.resize(static_cast<std::size_t>(p * p));
  grid.width_px = grid.height_px = std::clamp(350 * p, 700, 3500);
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const double scale = parameters[i].scale;
    grid.panels[i * static_cast<std::size_t>(p) + i] =
        marginal_panel(parameters[i], scale * samples[i].bottomRows(kept), scale * mean[i], scale * q025[i],
                       scale * q975[i], range[i]);
  }
  // The scatter samples: evenly spread over the kept (step, chain) pairs, step-major.
  const long total = kept * chains, shown = std::min(total, kMaxScatterPoints);
  std::vector<std::vector<double>> thinned(static_cast<std::size_t>(p));
  for (long j = 0; j < shown; ++j) {
    const long flat = j * total / shown, step = discard + flat / chains, chain = flat % chains;
    for (std::size_t k = 0; k < thinned.size(); ++k)
      thinned[k].push_back(parameters[k].scale * samples[k](step, chain));
  }
  for (std::size_t row = 1; row < thinned.size(); ++row)
    for (std::size_t column = 0; column < row; ++column) {
      io::LinePlot scatter{.x_label = parameters[column].label,
                           .y_label = parameters[row].label,
                           .x_range = range[column],
                           .y_range = range[row],
                           .max_ticks = kCornerMaxTicks};
      scatter.series.push_back(
          {.x = thinned[column], .y = thinned[row], .style = io::SeriesStyle::points, .color = "#a0204080"});
      grid.panels[row * static_cast<std::size_t>(p) + column] = std::move(scatter);
    }
  return grid;
}

io::LinePlot trace_plot(const CalibrationPosterior& posterior, const std::string& study_name, std::size_t k) {
  io::LinePlot trace;
  trace.title = study_name + ": trace of " + posterior.names[k] + " (all chains)";
  trace.x_label = "step";
  trace.y_label = posterior.names[k];
  for (int c = 0; c < posterior.chains; ++c) {
    io::Series series{.color = "#4060a0", .line_width = 0.5};
    for (long step = 0; step < posterior.steps; ++step) {
      series.x.push_back(static_cast<double>(step + 1));
      series.y.push_back(posterior.samples[k](step, c));
    }
    trace.series.push_back(std::move(series));
  }
  return trace;
}

io::LinePlot predictive_plot(const CalibrationPosterior& posterior, const CalibrationStudy& s, std::size_t c) {
  const PredictiveBand& band = posterior.predictive[c];
  const CalibrationDataset& data = s.datasets[c];
  io::LinePlot plot;
  plot.title = s.identity.name + ": posterior predictive 99.73 % band of " + data.channel + " (" +
               std::to_string(posterior.predictive_draws) + " draws, curve " + std::to_string(c) + ")";
  plot.x_label = "t (data clock) [s]";
  plot.y_label = data.channel + " [mm]";
  plot.bands.push_back({.label = "with measurement noise", .x = band.t, .lower = in_millimetres(band.lower_noise),
                        .upper = in_millimetres(band.upper_noise), .color = "#a0c0ff", .opacity = 0.4});
  plot.bands.push_back({.label = "model only", .x = band.t, .lower = in_millimetres(band.lower), .upper = in_millimetres(band.upper),
                        .color = "#2040a0", .opacity = 0.5});
  plot.series.push_back({.label = "data", .x = data.t, .y = in_millimetres(data.z), .style = io::SeriesStyle::points,
                         .color = "black", .line_width = 1.0});
  return plot;
}

}  // namespace

void plot_calibration_posterior(const CalibrationPosterior& posterior, const CalibrationStudy& s,
                                const std::string& stem) {
  for (std::size_t k = 0; k < posterior.names.size(); ++k)
    io::write_png_or_warn(trace_plot(posterior, s.identity.name, k), stem + "_trace_" + posterior.names[k] + ".png",
                          "calibrate", std::cerr);
  std::vector<CornerParameter> shown;
  for (const std::string& name : posterior.names) shown.push_back(corner_parameter(name));
  const long kept = posterior.steps - posterior.discard;
  io::write_png_or_warn(corner_plot(s.identity.name + ": posterior, " + std::to_string(kept) + " steps x " +
                                        std::to_string(posterior.chains) + " chains after " +
                                        std::to_string(posterior.discard) + " burn-in steps",
                                    shown, posterior.samples, posterior.discard, posterior.summary.mean,
                                    posterior.summary.q025, posterior.summary.q975),
                        stem + "_corner.png", "calibrate", std::cerr);
  for (std::size_t c = 0; c < posterior.predictive.size() && posterior.predictive_draws > 0; ++c)
    io::write_png_or_warn(predictive_plot(posterior, s, c),
                          stem + "_predictive" + (c == 0 ? std::string() : "_" + std::to_string(c)) + ".png",
                          "calibrate", std::cerr);
}

}  // namespace rover::study
