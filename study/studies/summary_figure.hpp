// The one figure every study writes by default beside its result file,
// <results>_summary.png: the study's panels (bands, histograms, convergence,
// indices, as fit the study) on one grid, at most kSummaryColumns wide.
// Also the panels more than one study draws: a QoI's histogram and its
// running mean against N.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "io/plot.hpp"
#include "study/estimators/qoi_summary.hpp"

namespace rover::study {

inline constexpr int kSummaryColumns = 3;

// Writes the panels (none: nothing) to `png_path`; a plot failure is a
// warning on the console labelled `command`, never an error.
void write_summary_figure(const std::string& title, const std::vector<io::LinePlot>& panels,
                          const std::string& png_path, const std::string& command);

// A histogram of the finite values (in display units), drawn as its outline,
// with the mean and, if `summary` is given, its confidence interval marked;
// nullopt with fewer than two finite values.
std::optional<io::LinePlot> histogram_panel(const std::string& name, const std::string& unit,
                                            const std::vector<double>& values, const QoiSummary* summary,
                                            double confidence);

// The running mean and sd of the finite values against N, at log-spaced N,
// each with its normal-theory interval at `confidence`; nullopt with fewer
// than two points.
struct ConvergencePanels {
  io::LinePlot mean, sd;
};
std::optional<ConvergencePanels> convergence_panels(const std::string& name, const std::string& unit,
                                                    const std::vector<double>& values, double confidence);

}  // namespace rover::study
