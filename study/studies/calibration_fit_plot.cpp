// The figures of a calibration fit (calibration_checked_fit.hpp): each curve's
// data with the fitted model, and each profile likelihood with its 95 %
// threshold.
#include <algorithm>
#include <iostream>

#include "io/plot.hpp"
#include "study/studies/calibration_checked_fit.hpp"
#include "study/studies/report_number.hpp"
#include "study/studies/report_format.hpp"

namespace rover::study {
namespace {

// The 0.95 quantile of chi-square with one degree of freedom.
constexpr double kChiSquare1At95 = 3.841458820694124;
constexpr double kMillimetresPerMetre = 1000.0;

io::LinePlot profile_plot(const ParameterProfile& prof, const std::string& study_name) {
  io::LinePlot plot;
  const double minimum = *std::min_element(prof.weighted_rss.begin(), prof.weighted_rss.end());
  plot.title = study_name + ": profile likelihood of " + prof.name +
               (prof.complete && !prof.interval.identifiable ? " (not identifiable from these data)" : "");
  plot.x_label = prof.name;
  plot.y_label = "(RSS - RSS_min) / s^2";
  io::Series curve{.label = "profile", .x = prof.values, .style = io::SeriesStyle::lines_points};
  for (double v : prof.weighted_rss) curve.y.push_back(v - minimum);
  io::Series threshold{.label = "95 % threshold (chi2_1 = 3.84)",
                       .x = {prof.values.front(), prof.values.back()},
                       .y = {kChiSquare1At95, kChiSquare1At95},
                       .style = io::SeriesStyle::dashed};
  plot.series = {curve, threshold};
  return plot;
}

io::LinePlot curve_plot(const CalibrationFitResult& r, const CalibrationStudy& s, std::size_t k) {
  const GaussNewtonResult& gn = r.checked.gn;
  io::LinePlot plot;
  plot.title = s.identity.name + ": data and fitted " + s.datasets[k].channel + " (RMS " +
               format_number(kMillimetresPerMetre * (gn.ok ? gn.noise_rms[k] : r.best_rms_m)) + " mm)";
  plot.x_label = "t (data clock) [s]";
  plot.y_label = s.datasets[k].channel + " [mm]";
  io::Series data{.label = "data", .x = s.datasets[k].t, .y = in_millimetres(s.datasets[k].z), .style = io::SeriesStyle::points};
  io::Series model{.label = "fitted model", .x = r.fitted_curves[k].t_s, .y = in_millimetres(r.fitted_curves[k].z_m)};
  plot.series = {data, model};
  return plot;
}

}  // namespace

void plot_calibration_fit(const CalibrationFitResult& r, const CalibrationStudy& s, const std::string& stem) {
  for (const ParameterProfile& prof : r.profiles)
    if (!prof.values.empty())
      io::write_png_or_warn(profile_plot(prof, s.identity.name), stem + "_profile_" + prof.name + ".png", "calibrate",
                            std::cerr);
  for (std::size_t k = 0; k < s.datasets.size(); ++k)
    io::write_png_or_warn(curve_plot(r, s, k), stem + (k == 0 ? "" : "_" + std::to_string(k)) + ".png", "calibrate",
                          std::cerr);
}

}  // namespace rover::study
