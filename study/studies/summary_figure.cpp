// See summary_figure.hpp.
#include "study/studies/summary_figure.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>
#include <tuple>

#include <boost/math/distributions/normal.hpp>

#include "study/studies/report_format.hpp"

namespace rover::study {
namespace {

constexpr int kMinHistogramBins = 5, kMaxHistogramBins = 60;
// Convergence points at N = 4, 5, 6, 8, ...: each 1.25 times the last.
constexpr double kFirstConvergencePoint = 4.0, kConvergencePointGrowth = 1.25;
// The canvas of one summary panel.
constexpr int kPanelWidthPx = 600, kPanelHeightPx = 420;
// Linear axes of a small panel get at most this many tick intervals.
constexpr int kPanelMaxTicks = 5;

// The two-sided normal quantile of a confidence level (1.96 for 0.95).
double normal_quantile_two_sided(double confidence) {
  return boost::math::quantile(boost::math::normal(), 0.5 + confidence / 2.0);
}

std::string percent_text(double confidence) { return percent_digits(confidence) + " %"; }

}  // namespace

std::optional<io::LinePlot> histogram_panel(const std::string& name, const std::string& unit,
                                            const std::vector<double>& values, const QoiSummary* summary,
                                            double confidence) {
  const DisplayUnit shown = display_unit(unit);
  std::vector<double> v;
  for (double x : values)
    if (std::isfinite(x)) v.push_back(x * shown.factor);
  if (v.size() < 2) return std::nullopt;
  const auto [lo_it, hi_it] = std::minmax_element(v.begin(), v.end());
  const double lo = *lo_it, hi = *hi_it;
  const int bins = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(v.size()))), kMinHistogramBins,
                              kMaxHistogramBins);
  const double width = hi > lo ? (hi - lo) / bins : 1.0;
  std::vector<double> counts(static_cast<std::size_t>(bins), 0.0);
  for (double x : v) counts[static_cast<std::size_t>(std::min(bins - 1, static_cast<int>((x - lo) / width)))] += 1;
  io::Series outline{"histogram"};
  for (int b = 0; b < bins; ++b) {
    const double left = lo + b * width;
    outline.x.insert(outline.x.end(), {left, left, left + width, left + width});
    const double c = counts[static_cast<std::size_t>(b)];
    outline.y.insert(outline.y.end(), {0.0, c, c, 0.0});
  }
  io::LinePlot plot;
  const double mean = std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  plot.title = name + ": " + std::to_string(v.size()) + " runs, mean " + std::to_string(mean) + " " + shown.name;
  plot.x_label = name + " [" + shown.name + "]";
  plot.y_label = "runs per bin";
  plot.series.push_back(outline);
  const double peak = *std::max_element(counts.begin(), counts.end());
  std::vector<std::pair<std::string, double>> marks{{"mean", mean}};
  if (summary != nullptr) {
    const std::string level = percent_text(confidence);
    marks = {{"mean", summary->mean * shown.factor},
             {"mean, lower " + level, summary->mean_lower * shown.factor},
             {"mean, upper " + level, summary->mean_upper * shown.factor}};
  }
  for (const auto& [label, x] : marks)
    if (std::isfinite(x)) plot.series.push_back({label, {x, x}, {0.0, peak}, io::SeriesStyle::dashed});
  return plot;
}

std::optional<ConvergencePanels> convergence_panels(const std::string& name, const std::string& unit,
                                                    const std::vector<double>& values, double confidence) {
  const DisplayUnit shown = display_unit(unit);
  const double k = shown.factor, z = normal_quantile_two_sided(confidence);
  const std::string level = percent_text(confidence);
  io::Series mean{"mean"}, sd{"sd"};
  io::Band mean_band{"mean, " + level}, sd_band{"sd, " + level};
  double m = 0.0, s2 = 0.0;
  int n = 0;
  double next = kFirstConvergencePoint;
  for (double x : values) {
    if (!std::isfinite(x)) continue;
    ++n;
    const double delta = x - m;
    m += delta / n;
    s2 += delta * (x - m);
    if (n < static_cast<int>(next) && n != static_cast<int>(values.size())) continue;
    next *= kConvergencePointGrowth;
    const double sd_n = std::sqrt(s2 / std::max(1, n - 1));
    const double half = z * sd_n / std::sqrt(static_cast<double>(n));
    const double sd_half = z * sd_n / std::sqrt(2.0 * std::max(1, n - 1));
    mean.x.push_back(n);
    mean.y.push_back(k * m);
    mean_band.x.push_back(n);
    mean_band.lower.push_back(k * (m - half));
    mean_band.upper.push_back(k * (m + half));
    sd.x.push_back(n);
    sd.y.push_back(k * sd_n);
    sd_band.x.push_back(n);
    sd_band.lower.push_back(k * (sd_n - sd_half));
    sd_band.upper.push_back(k * (sd_n + sd_half));
  }
  if (mean.x.size() < 2) return std::nullopt;
  ConvergencePanels plots;
  for (auto [plot, series, band, what] : {std::tuple{&plots.mean, &mean, &mean_band, "mean"},
                                          std::tuple{&plots.sd, &sd, &sd_band, "sd"}}) {
    plot->title = name + ": running " + std::string(what) + " against N";
    plot->x_label = "N";
    plot->y_label = name + " " + what + " [" + shown.name + "]";
    plot->log_x = true;
    plot->series.push_back(*series);
    plot->bands.push_back(*band);
  }
  return plots;
}

void write_summary_figure(const std::string& title, const std::vector<io::LinePlot>& panels,
                          const std::string& png_path, const std::string& command) {
  if (panels.empty()) return;
  const int n = static_cast<int>(panels.size());
  io::PanelGrid grid;
  grid.title = title;
  grid.cols = std::min(n, kSummaryColumns);
  grid.rows = (n + grid.cols - 1) / grid.cols;
  for (const io::LinePlot& p : panels) {
    grid.panels.emplace_back(p);
    grid.panels.back()->max_ticks = kPanelMaxTicks;
  }
  grid.panels.resize(static_cast<std::size_t>(grid.rows * grid.cols));
  grid.width_px = grid.cols * kPanelWidthPx;
  grid.height_px = grid.rows * kPanelHeightPx;
  io::write_png_or_warn(grid, png_path, command, std::cerr);
}

}  // namespace rover::study
