// The sensitivity study's figures (sensitivity.hpp): Sobol' indices with
// their intervals per QoI, along time per channel, and the Morris mu*-sigma
// plane per QoI.
#include <algorithm>
#include <iostream>

#include "io/plot.hpp"
#include "study/studies/report_format.hpp"
#include "study/studies/sensitivity.hpp"
#include "study/studies/study_output.hpp"

namespace rover::study {
namespace {

// Inputs whose aggregated total index exceeds this are drawn along time.
constexpr double kPlottedTotalIndex = 0.01;
// Room beside the largest Morris effects for their labels.
constexpr double kMorrisLabelRoomX = 1.3, kMorrisLabelRoomY = 1.15;

void plot_sobol(const std::string& png, const std::string& qoi, const SobolIndices& s,
                const std::vector<std::string>& labels, double confidence) {
  io::BarPlot plot;
  plot.title = qoi + ": Sobol' indices (" + std::to_string(s.groups_used) + " groups), " +
               std::to_string(static_cast<int>(100 * confidence)) + " % intervals";
  plot.y_label = "index";
  plot.categories = labels;
  plot.groups.push_back({"S1 (first order)", to_vector(s.S1), to_vector(s.S1_lower), to_vector(s.S1_upper)});
  plot.groups.push_back({"ST (total)", to_vector(s.ST), to_vector(s.ST_lower), to_vector(s.ST_upper)});
  io::write_png_or_warn(plot, png, "sensitivity", std::cerr);
}

// S_i(t) of the inputs that matter, under the output variance V(t).
void plot_sobol_t(const std::string& png, const std::string& channel, const SobolIndicesAlongTime& s,
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
  if (!indices.series.empty()) io::write_png_or_warn(indices, png, "sensitivity", std::cerr);
  io::LinePlot variance;
  variance.title = channel + ": output variance along time";
  variance.x_label = "t [s]";
  variance.y_label = "Var " + channel;
  variance.series.push_back({"V(t)", t, to_vector(s.variance)});
  io::write_png_or_warn(variance, sibling_path(png, "_variance.png"), "sensitivity", std::cerr);
}

void plot_morris(const std::string& png, const std::string& qoi, const MorrisResult& m,
                 const std::vector<std::string>& labels) {
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
  io::write_png_or_warn(plot, png, "sensitivity", std::cerr);
}

}  // namespace

void plot_sensitivity(const SensitivityResult& result, const std::string& results_path, PlotSelection plots) {
  if (plots == PlotSelection::kNone) return;
  const SensitivityStudy& study = result.study;
  const StudyModel& model = *study.spec.model;
  const std::vector<std::string> labels = input_labels(study.spec);
  auto png = [&](const std::string& suffix) { return sibling_path(results_path, suffix); };
  if (study.method == SensitivityMethod::kPce) plot_pce_sensitivity(results_path, study.spec, result.pce);
  for (std::size_t q = 0; q < result.sobol.size(); ++q)
    plot_sobol(png("_sobol_" + model.qoi_names()[q] + ".png"), model.qoi_names()[q], result.sobol[q], labels,
               study.sobol.confidence);
  for (std::size_t c = 0; c < result.sobol_t.size(); ++c)
    plot_sobol_t(png("_sobol_t_" + model.channel_names()[c] + ".png"), model.channel_names()[c], result.sobol_t[c],
                 model.time_s(), labels);
  for (std::size_t q = 0; q < result.morris.size(); ++q)
    plot_morris(png("_morris_" + model.qoi_names()[q] + ".png"), model.qoi_names()[q], result.morris[q], labels);
}

}  // namespace rover::study
