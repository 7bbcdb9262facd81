// The Monte Carlo study's figures (montecarlo.hpp): the band of each channel,
// the histogram of each QoI and the convergence of its mean and sd with N.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <tuple>

#include <boost/math/distributions/normal.hpp>

#include "io/plot.hpp"
#include "study/studies/report_format.hpp"
#include "study/studies/montecarlo.hpp"
#include "study/studies/study_output.hpp"

namespace rover::study {
namespace {

constexpr int kMinHistogramBins = 5, kMaxHistogramBins = 60;
// Convergence points at N = 4, 5, 6, 8, ...: each 1.25 times the last.
constexpr double kFirstConvergencePoint = 4.0, kConvergencePointGrowth = 1.25;

std::vector<double> scaled(const std::vector<double>& v, double factor) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [&](double x) { return factor * x; });
  return out;
}

// The two-sided normal quantile of a confidence level (1.96 for 0.95).
double normal_quantile_two_sided(double confidence) {
  return boost::math::quantile(boost::math::normal(), 0.5 + confidence / 2.0);
}

std::string percent_text(double confidence) { return std::to_string(static_cast<int>(100 * confidence)) + " %"; }

io::LinePlot band_plot(const std::string& title, const std::string& channel, const std::string& unit,
                       const std::vector<double>& t, const Band& band) {
  const DisplayUnit shown = display_unit(unit);
  io::LinePlot plot;
  plot.title = title + ": " + channel + ", " + std::to_string(band.samples_used) + " runs";
  plot.x_label = "t [s]";
  plot.y_label = channel + " [" + shown.name + "]";
  plot.bands.push_back({"mean -+ 3 sd", t, scaled(band.lower, shown.factor), scaled(band.upper, shown.factor)});
  plot.series.push_back({"mean", t, scaled(band.mean, shown.factor)});
  plot.series.push_back({"0.135 % quantile", t, scaled(band.p00135, shown.factor), io::SeriesStyle::dashed});
  plot.series.push_back({"99.865 % quantile", t, scaled(band.p99865, shown.factor), io::SeriesStyle::dashed});
  return plot;
}

// A histogram drawn as its outline, with the mean and its interval marked;
// nullopt with fewer than two finite values.
std::optional<io::LinePlot> histogram_plot(const std::string& name, const std::string& unit,
                                           const std::vector<double>& values, const QoiSummary& summary,
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
  plot.title = name + ": " + std::to_string(v.size()) + " runs, mean " + std::to_string(summary.mean * shown.factor) +
               " " + shown.name;
  plot.x_label = name + " [" + shown.name + "]";
  plot.y_label = "runs per bin";
  plot.series.push_back(outline);
  const double peak = *std::max_element(counts.begin(), counts.end());
  const std::string level = percent_text(confidence);
  for (const auto& [label, x] : {std::pair{std::string("mean"), summary.mean},
                                 std::pair{"mean, lower " + level, summary.mean_lower},
                                 std::pair{"mean, upper " + level, summary.mean_upper}}) {
    if (!std::isfinite(x)) continue;
    const double xd = x * shown.factor;
    plot.series.push_back({label, {xd, xd}, {0.0, peak}, io::SeriesStyle::dashed});
  }
  return plot;
}

// Running mean and sd of a QoI against N with their intervals (normal theory,
// at log-spaced N): how far the estimates have settled. Empty with fewer than
// two points.
struct ConvergencePlots {
  io::LinePlot mean, sd;
};
std::optional<ConvergencePlots> convergence_plots(const std::string& name, const std::string& unit,
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
  ConvergencePlots plots;
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

}  // namespace

void plot_montecarlo(const MonteCarloResult& result, const std::string& results_path, PlotSelection plots) {
  if (plots == PlotSelection::kNone) return;
  const StudySpec& spec = result.study.spec;
  const StudyModel& model = *spec.model;
  const double confidence = result.study.confidence;
  auto png = [&](const std::string& suffix) { return sibling_path(results_path, suffix); };
  for (std::size_t c = 0; c < result.bands.size(); ++c) {
    const std::string& name = model.channel_names()[c];
    io::write_png_or_warn(band_plot(spec.name, name, channel_unit(channel_from_name(name)), model.time_s(),
                                    result.bands[c]),
                          png("_band_" + name + ".png"), "montecarlo", std::cerr);
  }
  for (std::size_t q = 0; q < result.qoi.size(); ++q) {
    const std::string& name = model.qoi_names()[q];
    const std::string& unit = model.qoi_units()[q];
    if (const auto h = histogram_plot(name, unit, result.qoi[q], result.summaries[q], confidence))
      io::write_png_or_warn(*h, png("_hist_" + name + ".png"), "montecarlo", std::cerr);
    if (const auto c = convergence_plots(name, unit, result.qoi[q], confidence)) {
      io::write_png_or_warn(c->mean, png("_convergence_" + name + "_mean.png"), "montecarlo", std::cerr);
      io::write_png_or_warn(c->sd, png("_convergence_" + name + "_sd.png"), "montecarlo", std::cerr);
    }
  }
}

}  // namespace rover::study
