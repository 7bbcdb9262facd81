// See surrogate_report.hpp.
#include "study/studies/surrogate_report.hpp"

#include <algorithm>
#include <filesystem>
#include <cmath>
#include <iomanip>
#include <numeric>
#include <ostream>
#include <sstream>

#include "io/plot.hpp"
#include "study/studies/study_output.hpp"
#include "study/studies/report_format.hpp"

namespace rover::study {
namespace {

constexpr int kSurrogateLabelWidth = 24;
constexpr int kMaxPanelColumns = 3;
constexpr int kSurrogatePanelWidthPx = 520, kSurrogatePanelHeightPx = 480;

std::string general(double x) {
  std::ostringstream os;
  os << std::setprecision(6) << x;
  return os.str();
}

// The QoIs and statuses of runs under prefix (their inputs are written by the caller).
void write_runs(io::Hdf5Writer& h5, const std::string& prefix, const SurrogateStudy& study, const TrainingRuns& runs) {
  const std::vector<std::string> qois = study.qoi_names();
  for (std::size_t q = 0; q < qois.size(); ++q)
    h5.write(prefix + "/qoi/" + qois[q], to_vector(runs.y.col(static_cast<Eigen::Index>(q))));
  if (study.spec.rover) write_qoi_definitions(h5, study.spec.rover->qois(), prefix);
  h5.write(prefix + "/samples/status", runs.status);
  h5.write(prefix + "/samples/message", runs.messages);
}

void write_indices(io::Hdf5Writer& h5, const SurrogateQoiResult& q, const PceSensitivityOptions& options) {
  const std::string group = "/indices/" + q.name, g = group + "/";
  h5.create_group(group);
  h5.attribute(group, "defined", static_cast<long long>(q.indices_defined ? 1 : 0));
  h5.attribute(group, "undefined_reason", q.undefined_reason);
  h5.attribute(group, "runs_used", static_cast<long long>(q.runs_used));
  if (!q.fitted) return;
  h5.write(g + "mean", std::vector<double>{q.indices.mean});
  h5.write(g + "variance", std::vector<double>{q.indices.variance});
  if (!q.indices_defined) return;
  h5.write(g + "S1", to_vector(q.indices.S1));
  h5.write(g + "ST", to_vector(q.indices.ST));
  h5.attribute(g + "S1", "confidence", options.confidence);
  h5.attribute(g + "S1", "bootstrap_resamples", static_cast<long long>(options.bootstrap));
  if (!q.has_intervals) return;
  h5.attribute(g + "S1", "resamples_used", static_cast<long long>(q.intervals.resamples_used));
  h5.write(g + "S1_lower", to_vector(q.intervals.S1_lower));
  h5.write(g + "S1_upper", to_vector(q.intervals.S1_upper));
  h5.write(g + "ST_lower", to_vector(q.intervals.ST_lower));
  h5.write(g + "ST_upper", to_vector(q.intervals.ST_upper));
  write_pce_fixed_by_selection(h5, g, q.intervals);
}

void write_validation(io::Hdf5Writer& h5, const SurrogateQoiResult& q) {
  if (!q.fitted) return;
  const std::string g = "/validation/" + q.name + "/";
  h5.write(g + "actual", to_vector(q.actual));
  h5.write(g + "loo_predicted", to_vector(q.loo_predicted));
  if (q.held_out_actual.size() == 0) return;
  h5.write(g + "held_out_actual", to_vector(q.held_out_actual));
  h5.write(g + "held_out_predicted", to_vector(q.held_out_predicted));
}

// The held-out Q2, or "undefined" (fewer than 2 held-out runs, or equal values).
std::string held_out_q2_text(const SurrogateValidation& v) {
  return std::isfinite(v.q2_test) ? fixed_text(v.q2_test, 4) : "undefined";
}

// The leave-one-out Q2, or "undefined" for an output without variance
// (1 - PRESS / SST is 0 / 0 there).
std::string loo_q2_text(const FittedSurrogate& m) {
  const bool constant = m.kind == SurrogateKind::kPolynomialChaos && m.pce.constant_output;
  return constant ? "undefined (constant output)" : fixed_text(m.validation().q2_loo, 4);
}

std::string validation_text(const FittedSurrogate& m) {
  const SurrogateValidation& v = m.validation();
  std::string s = "Q2 LOO " + loo_q2_text(m) + reselected_q2_text(v);
  if (v.test_points > 0)
    s += ", held-out Q2 " + held_out_q2_text(v) + " (RMSE " + general(v.rmse_test) + ", " +
         std::to_string(v.test_points) + (v.test_points == 1 ? " run)" : " runs)");
  return s;
}

std::string model_text(const FittedSurrogate& m, const std::vector<std::string>& labels) {
  if (m.kind == SurrogateKind::kPolynomialChaos)
    return "PCE degree " + std::to_string(m.pce.degree) + ", " + std::to_string(m.pce.multi_indices.size()) +
           " of " + std::to_string(m.pce.candidate_terms) + " terms";
  std::string s = std::string("GP, ") + (m.gp.trend == KrigingTrend::kConstant ? "constant" : "linear") +
                  " trend, length-scales on F(x):";
  for (Eigen::Index i = 0; i < m.gp.length_scales.size(); ++i)
    s += " " + labels[static_cast<std::size_t>(i)] + " " + general(m.gp.length_scales(i));
  return s;
}

void report_indices(std::ostream& out, const SurrogateQoiResult& q, const std::vector<std::string>& labels) {
  const auto interval = [&](const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, const std::vector<bool>& fixed,
                            Eigen::Index i) { return q.has_intervals ? pce_interval_text(lo, hi, fixed, i) : ""; };
  std::vector<Eigen::Index> order(static_cast<std::size_t>(q.indices.ST.size()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return q.indices.ST(a) > q.indices.ST(b); });
  for (Eigen::Index i : order)
    out << "  " << std::left << std::setw(kSurrogateLabelWidth) << labels[static_cast<std::size_t>(i)] << std::right << " S1 "
        << std::setw(6) << fixed_text(q.indices.S1(i)) << " " << std::setw(16)
        << interval(q.intervals.S1_lower, q.intervals.S1_upper, q.intervals.fixed_by_selection.S1, i) << "   ST "
        << std::setw(6) << fixed_text(q.indices.ST(i)) << " "
        << interval(q.intervals.ST_lower, q.intervals.ST_upper, q.intervals.fixed_by_selection.ST, i) << "\n";
  if (q.has_intervals) out << pce_fixed_by_selection_note(q.intervals);
}

void report_qoi(std::ostream& out, const SurrogateQoiResult& q, const std::vector<std::string>& labels,
                double confidence) {
  if (!q.fitted) {
    out << q.name << ": no surrogate: " << q.undefined_reason << "\n";
    return;
  }
  out << q.name << ": " << model_text(q.model, labels) << "; " << q.runs_used << " runs; "
      << validation_text(q.model);
  if (q.model.kind == SurrogateKind::kPolynomialChaos)
    out << "; mean " << general(q.indices.mean) << ", sd " << general(std::sqrt(q.indices.variance));
  out << "\n";
  if (!q.indices_defined) {
    if (q.model.kind == SurrogateKind::kPolynomialChaos) out << "  indices undefined: " << q.undefined_reason << "\n";
    return;
  }
  if (q.has_intervals)
    out << "  Sobol' indices by total index, " << percent_digits(confidence) << " % bootstrap intervals ("
        << q.intervals.resamples_used << " resamples):\n";
  report_indices(out, q, labels);
}

std::optional<io::LinePlot> predicted_panel(const SurrogateQoiResult& q) {
  if (!q.fitted || q.actual.size() == 0) return std::nullopt;
  io::LinePlot p;
  const SurrogateValidation& v = q.model.validation();
  p.title = q.name + ": Q2 LOO " + loo_q2_text(q.model) + (v.test_points > 0 ? ", held-out " + held_out_q2_text(v) : "");
  p.x_label = "model";
  p.y_label = "surrogate";
  p.max_ticks = 4;
  p.series.push_back({"leave-one-out", to_vector(q.actual), to_vector(q.loo_predicted), io::SeriesStyle::points});
  double lo = std::min(q.actual.minCoeff(), q.loo_predicted.minCoeff());
  double hi = std::max(q.actual.maxCoeff(), q.loo_predicted.maxCoeff());
  if (q.held_out_actual.size() > 0) {
    p.series.push_back({"held out", to_vector(q.held_out_actual), to_vector(q.held_out_predicted),
                        io::SeriesStyle::points});
    lo = std::min({lo, q.held_out_actual.minCoeff(), q.held_out_predicted.minCoeff()});
    hi = std::max({hi, q.held_out_actual.maxCoeff(), q.held_out_predicted.maxCoeff()});
  }
  p.series.push_back({"y = x", {lo, hi}, {lo, hi}, io::SeriesStyle::dashed, "black", 1.0});
  return p;
}

void plot_predicted(const std::string& png, const SurrogateStudyResult& r, std::ostream& log) {
  std::vector<std::optional<io::LinePlot>> panels;
  for (const SurrogateQoiResult& q : r.qoi)
    if (auto p = predicted_panel(q)) panels.push_back(std::move(p));
  if (panels.empty()) return;
  const int cols = std::min(kMaxPanelColumns, static_cast<int>(panels.size()));
  const int rows = (static_cast<int>(panels.size()) + cols - 1) / cols;
  panels.resize(static_cast<std::size_t>(rows * cols));
  io::PanelGrid grid{.title = "surrogate against model", .rows = rows, .cols = cols, .panels = std::move(panels),
                     .width_px = cols * kSurrogatePanelWidthPx, .height_px = rows * kSurrogatePanelHeightPx};
  io::write_png_or_warn(grid, png, "surrogate", log);
}

void plot_indices(const std::string& png, const SurrogateStudy& study, const SurrogateStudyResult& r,
                  std::ostream& log) {
  io::BarPlot plot;
  plot.title = "Total Sobol' indices from the PCE, " + percent_digits(study.pce.confidence) +
               " % bootstrap intervals" +
               (study.compare_file.empty() ? std::string()
                                            : ", beside those of " +
                                                  std::filesystem::path(study.compare_file).filename().string());
  plot.y_label = "ST";
  plot.y_range = io::AxisRange{0.0, 1.05};
  plot.categories = input_labels(study.spec);
  for (std::size_t k = 0; k < r.qoi.size(); ++k) {
    const SurrogateQoiResult& q = r.qoi[k];
    if (!q.indices_defined) continue;
    const bool compared = k < r.compared.size() && r.compared[k].ST.size() > 0;
    io::BarGroup g{q.name + (compared ? " (PCE)" : ""), to_vector(q.indices.ST), to_vector(q.indices.ST),
                   to_vector(q.indices.ST)};
    if (q.has_intervals) {
      g.lower = to_vector(q.intervals.ST_lower);
      g.upper = to_vector(q.intervals.ST_upper);
    }
    plot.groups.push_back(std::move(g));
    if (compared)
      plot.groups.push_back({q.name + " (pick-freeze)", to_vector(r.compared[k].ST), to_vector(r.compared[k].ST_lower),
                             to_vector(r.compared[k].ST_upper)});
  }
  if (!plot.groups.empty()) io::write_png_or_warn(plot, png, "surrogate", log);
}

// Per channel: the mean and the mean +- 3 sd along time from the PCE.
void plot_band(const std::string& png, const PceChannelResult& c, const std::vector<double>& t, std::ostream& log) {
  io::LinePlot plot;
  plot.title = c.name + ": mean and mean +- 3 sd along time, from the PCE";
  plot.x_label = "t [s]";
  plot.y_label = c.name;
  const Eigen::VectorXd lower = c.indices.mean - 3.0 * c.indices.sd, upper = c.indices.mean + 3.0 * c.indices.sd;
  plot.bands.push_back({"mean +- 3 sd", t, to_vector(lower), to_vector(upper)});
  plot.series.push_back({"mean", t, to_vector(c.indices.mean)});
  io::write_png_or_warn(plot, png, "surrogate", log);
}

}  // namespace

void write_surrogate_study(io::Hdf5Writer& h5, const SurrogateStudy& study, const SurrogateStudyResult& r) {
  write_study_provenance(h5, study.spec, study.spec.fingerprint,
                         r.training.integrator ? &*r.training.integrator : nullptr);
  write_study_inputs(h5, study.spec, r.training.x);
  write_runs(h5, "", study, r.training);
  if (r.held_out.runs() > 0) {
    h5.write("/held_out/inputs/values", Eigen::MatrixXd(r.held_out.x));
    write_runs(h5, "/held_out", study, r.held_out);
  }
  h5.attribute("/", "samples", static_cast<long long>(r.training.runs() + r.held_out.runs()));
  if (!study.training_file.empty()) h5.attribute("/", "design", "none: the runs of the training file");
  h5.attribute("/", "surrogate", surrogate_kind_name(study.kind));
  h5.attribute("/", "training", r.training.source);
  h5.attribute("/", "runs", static_cast<long long>(r.training.runs()));
  h5.attribute("/", "failed_runs", static_cast<long long>(r.training.failed_runs()));
  h5.attribute("/", "held_out_runs", static_cast<long long>(r.held_out.runs()));
  h5.attribute("/", "held_out_source", r.held_out.runs() > 0 ? r.held_out.source : std::string());
  h5.attribute("/", "runs_wall_time_s", r.runs_wall_time_s);
  h5.attribute("/", "fit_wall_time_s", r.fit_wall_time_s);
  write_surrogate_set(h5, r.set);
  std::vector<std::string> undefined;
  for (const SurrogateQoiResult& q : r.qoi) {
    if (study.kind == SurrogateKind::kPolynomialChaos) write_indices(h5, q, study.pce);
    if (study.kind == SurrogateKind::kPolynomialChaos && !q.indices_defined) undefined.push_back(q.name);
    write_validation(h5, q);
  }
  write_undefined_indices(h5, undefined);
  if (!r.channels.empty()) h5.write("/t", study.spec.model->time_s());
  for (const PceChannelResult& c : r.channels) write_pce_channel(h5, c);
}

void report_surrogate_study(std::ostream& out, const SurrogateStudy& study, const SurrogateStudyResult& r) {
  out << "surrogate: " << surrogate_kind_name(study.kind) << " of " << r.qoi.size() << " QoI(s) over "
      << study.spec.inputs.size() << " inputs from " << r.training.runs() << " runs (" << r.training.failed_runs()
      << " failed) of " << r.training.source;
  if (r.held_out.runs() > 0) out << ", validated on " << r.held_out.runs() << " held-out runs";
  out << "; runs " << fixed_text(r.runs_wall_time_s, 1) << " s, fit " << fixed_text(r.fit_wall_time_s, 2) << " s\n";
  const std::vector<std::string> labels = input_labels(study.spec);
  for (const SurrogateQoiResult& q : r.qoi) report_qoi(out, q, labels, study.pce.confidence);
  for (const PceChannelResult& c : r.channels) {
    if (!c.defined) continue;
    out << c.name << " along time (PCE, " << c.curves.multi_indices.size() << " shared terms), variance-weighted:";
    for (std::size_t i = 0; i < labels.size(); ++i)
      out << " " << labels[i] << " S1 " << fixed_text(c.indices.aggregated_S1(static_cast<Eigen::Index>(i))) << " ST "
          << fixed_text(c.indices.aggregated_ST(static_cast<Eigen::Index>(i))) << (i + 1 < labels.size() ? ";" : "");
    out << "\n";
  }
  for (const std::string& w : r.warnings) out << "surrogate: warning: " << w << "\n";
}

std::vector<PlannedFigure> surrogate_figures(const SurrogateStudy& study) {
  std::vector<PlannedFigure> figures{{"_surrogate.png", "the predictions against the model"}};
  if (study.kind == SurrogateKind::kPolynomialChaos) figures.push_back({"_surrogate_indices.png", "the indices"});
  for (const std::string& c : study.spec.model->channel_names()) {
    figures.push_back({"_surrogate_t_" + c + ".png", "channel '" + c + "' (its indices along time)"});
    figures.push_back({"_surrogate_band_" + c + ".png", "channel '" + c + "' (its band)"});
  }
  return figures;
}

void plot_surrogate_study(const SurrogateStudy& study, const SurrogateStudyResult& r, std::ostream& log) {
  plot_predicted(sibling_path(r.results_path, "_surrogate.png"), r, log);
  if (study.kind == SurrogateKind::kPolynomialChaos)
    plot_indices(sibling_path(r.results_path, "_surrogate_indices.png"), study, r, log);
  const std::vector<double>& t = study.spec.model->time_s();
  for (const PceChannelResult& c : r.channels) {
    if (!c.defined) continue;
    plot_pce_channel(sibling_path(r.results_path, "_surrogate_t_" + c.name + ".png"), c, t, input_labels(study.spec),
                     "surrogate");
    plot_band(sibling_path(r.results_path, "_surrogate_band_" + c.name + ".png"), c, t, log);
  }
}

}  // namespace rover::study
