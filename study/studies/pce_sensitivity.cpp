// Sobol' indices from sparse polynomial chaos (Blatman & Sudret 2011; Sudret
// 2008): see pce_sensitivity.hpp.
#include "study/studies/pce_sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "core/name_list.hpp"
#include "core/number_text.hpp"
#include "io/plot.hpp"
#include "study/estimators/bootstrap_resolution.hpp"
#include "study/estimators/work_stopped.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/report_format.hpp"
#include "study/studies/reselected_cross_validation_output.hpp"
#include "study/studies/study_output.hpp"

namespace rover::study {
namespace {

// Channels: enough principal components for this share of the variance.
constexpr double kCurveExplainedVariance = 0.99;
// Inputs whose aggregated total index exceeds this are drawn along time.
// Bootstrap intervals need at least this share of the resamples refitted: a
// resample of too few distinct runs leaves the basis singular, and the
// percentiles of the few that fit are no interval.
constexpr double kMinUsedResampleShare = 0.5;

std::vector<Distribution> input_distributions(const StudySpec& spec) {
  std::vector<Distribution> d;
  for (const UncertainInput& in : spec.inputs) d.push_back(in.distribution);
  return d;
}

// The successful runs: their indices in run order.
std::vector<Eigen::Index> ok_runs(const std::vector<RunRecord>& records) {
  std::vector<Eigen::Index> ok;
  for (std::size_t i = 0; i < records.size(); ++i)
    if (records[i].ok()) ok.push_back(static_cast<Eigen::Index>(i));
  return ok;
}

DesignMatrix rows_of(const DesignMatrix& x, const std::vector<Eigen::Index>& rows) {
  DesignMatrix out(static_cast<Eigen::Index>(rows.size()), x.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = x.row(rows[k]);
  return out;
}

std::string undefined_because_non_finite(const Eigen::MatrixXd& y) {
  const auto bad = static_cast<long>((!y.array().isFinite()).rowwise().any().count());
  if (bad == 0) return "";
  return std::to_string(bad) + " of " + std::to_string(y.rows()) +
         " successful runs gave a non-finite value, so the indices are undefined";
}

// A channel whose spread over the runs is below this fraction of its size varies by rounding only.
constexpr double kRoundingRelative = 1e-12;

PceChannelResult channel_indices(const std::string& name, const DesignMatrix& x_ok, const Eigen::MatrixXd& y_ok,
                                 const std::vector<Distribution>& inputs, const PceSensitivityOptions& options) {
  PceChannelResult c;
  c.name = name;
  c.undefined_reason = undefined_because_non_finite(y_ok);
  if (!c.undefined_reason.empty()) return c;
  PolynomialChaosCurvesSettings settings;
  settings.pce = options.settings;
  settings.pce.stop = &InterruptGuard::flag();  // a signal ends the fit at its next step
  settings.explained_variance = kCurveExplainedVariance;
  try {
    c.curves = fit_polynomial_chaos_curves(x_ok, y_ok, inputs, settings, name);
  } catch (const std::invalid_argument& e) {
    c.undefined_reason = e.what();
    return c;
  }
  c.indices = curve_sobol_indices(c.curves);
  c.defined = c.indices.aggregated_defined;
  if (c.defined) return c;
  const bool varies = y_ok.rows() > 0 && (y_ok.colwise().maxCoeff() - y_ok.colwise().minCoeff()).maxCoeff() >
                                            kRoundingRelative * y_ok.cwiseAbs().maxCoeff();
  c.undefined_reason = varies ? "the channel varies over the runs, but its expansion selected no term beyond the "
                                "constant: no input explains its variance at this size; use more runs, or a "
                                "higher pce.max_degree"
                              : "the channel does not vary over the runs";
  return c;
}

void write_qoi(io::Hdf5Writer& h5, const PceQoiResult& q, const PceSensitivityOptions& options) {
  const std::string group = "/indices/" + q.name, g = group + "/";
  const PceSobolIndices& s = q.indices;
  h5.create_group(group);
  h5.attribute(group, "defined", static_cast<long long>(s.defined ? 1 : 0));
  h5.attribute(group, "undefined_reason", q.undefined_reason);
  h5.attribute(group, "runs_used", static_cast<long long>(q.runs_used));
  if (q.fit_done) {  // a constant QoI has its mean and a zero variance
    h5.write(g + "mean", std::vector<double>{s.mean});
    h5.write(g + "variance", std::vector<double>{s.variance});
  }
  if (s.defined) {
    h5.write(g + "S1", to_vector(s.S1));
    h5.write(g + "ST", to_vector(s.ST));
    h5.attribute(g + "S1", "confidence", options.confidence);
    h5.attribute(g + "S1", "bootstrap_resamples", static_cast<long long>(options.bootstrap));
    h5.attribute(g + "S1", "resamples_used", static_cast<long long>(q.intervals.resamples_used));
  }
  if (q.has_intervals) {
    h5.write(g + "S1_lower", to_vector(q.intervals.S1_lower));
    h5.write(g + "S1_upper", to_vector(q.intervals.S1_upper));
    h5.write(g + "ST_lower", to_vector(q.intervals.ST_lower));
    h5.write(g + "ST_upper", to_vector(q.intervals.ST_upper));
    write_pce_fixed_by_selection(h5, g, q.intervals);
  }
  if (!q.fit_done) return;
  const PolynomialChaosExpansion& e = q.expansion;
  const std::string p = "/pce/" + q.name + "/";
  Eigen::MatrixXd alpha(static_cast<Eigen::Index>(e.multi_indices.size()),
                        static_cast<Eigen::Index>(e.inputs.size()));
  for (std::size_t k = 0; k < e.multi_indices.size(); ++k)
    for (std::size_t i = 0; i < e.inputs.size(); ++i)
      alpha(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = e.multi_indices[k][i];
  h5.write(p + "q2_loo", std::vector<double>{e.validation.q2_loo});
  write_reselected_cross_validation(h5, p + "q2_loo", e.validation.reselected);
  h5.write(p + "degree", std::vector<int>{e.degree});
  h5.write(p + "terms", std::vector<int>{static_cast<int>(e.multi_indices.size())});
  h5.write(p + "multi_indices", alpha);
  h5.write(p + "coefficients", to_vector(e.coefficients));
  h5.attribute(p + "coefficients", "q_norm", e.q_norm);
  h5.attribute(p + "coefficients", "candidate_terms", static_cast<long long>(e.candidate_terms));
  h5.attribute(p + "coefficients", "runs", static_cast<long long>(e.runs));
  h5.attribute(p + "coefficients", "warning", e.validation.warning);
}

void write_channel(io::Hdf5Writer& h5, const PceChannelResult& c) {
  const std::string g = "/indices_t/" + c.name + "/";
  if (!c.defined) {
    h5.write(g + "undefined_reason", std::vector<std::string>{c.undefined_reason});
    return;
  }
  const CurveSobolIndices& s = c.indices;
  h5.write(g + "S1", Eigen::MatrixXd(s.S1.transpose()));  // d x T, as the pick-freeze results
  h5.write(g + "ST", Eigen::MatrixXd(s.ST.transpose()));
  h5.write(g + "variance", to_vector(s.sd.array().square().matrix()));
  h5.write(g + "mean", to_vector(s.mean));
  h5.write(g + "sd", to_vector(s.sd));
  h5.write(g + "q2_loo", to_vector(c.curves.q2_loo));
  h5.write("/aggregated/" + c.name + "/S1", to_vector(s.aggregated_S1));
  h5.write("/aggregated/" + c.name + "/ST", to_vector(s.aggregated_ST));
  Eigen::MatrixXd alpha(static_cast<Eigen::Index>(c.curves.multi_indices.size()),
                        static_cast<Eigen::Index>(c.curves.inputs.size()));
  for (std::size_t k = 0; k < c.curves.multi_indices.size(); ++k)
    for (std::size_t i = 0; i < c.curves.inputs.size(); ++i)
      alpha(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = c.curves.multi_indices[k][i];
  h5.write("/pce_t/" + c.name + "/multi_indices", alpha);
  h5.write("/pce_t/" + c.name + "/coefficients", c.curves.coefficients);
  h5.attribute("/pce_t/" + c.name + "/coefficients", "components", static_cast<long long>(c.curves.components));
}

std::string interval(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper, const std::vector<bool>& fixed,
                     Eigen::Index i, bool has) {
  return has ? pce_interval_text(lower, upper, fixed, i) : "";
}

void print_qoi(std::ostream& out, const PceQoiResult& q, const std::vector<std::string>& labels, double confidence) {
  if (!q.indices.defined) {
    out << q.name << ": indices undefined: " << q.undefined_reason << "\n";
    return;
  }
  const PceSobolIndices& s = q.indices;
  const PceSobolIntervals& ci = q.intervals;
  out << q.name << " (PCE degree " << q.expansion.degree << ", " << q.expansion.multi_indices.size() << " terms, "
      << q.runs_used << " runs, Q2_LOO " << fixed_text(q.expansion.validation.q2_loo, 4)
      << reselected_q2_text(q.expansion.validation) << "; mean " << s.mean
      << ", variance " << s.variance;
  if (q.has_intervals)
    out << "; " << percent_digits(confidence) << " % bootstrap intervals, "
        << ci.resamples_used << " resamples";
  out << "), by total index:\n";
  std::vector<Eigen::Index> order(static_cast<std::size_t>(s.ST.size()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return s.ST[a] > s.ST[b]; });
  for (Eigen::Index i : order)
    out << "  " << std::left << std::setw(kIndexLabelWidth) << labels[static_cast<std::size_t>(i)] << std::right
        << " S1 " << std::setw(6) << fixed_text(s.S1[i]) << " " << std::setw(16)
        << interval(ci.S1_lower, ci.S1_upper, ci.fixed_by_selection.S1, i, q.has_intervals) << "   ST "
        << std::setw(6) << fixed_text(s.ST[i]) << " "
        << interval(ci.ST_lower, ci.ST_upper, ci.fixed_by_selection.ST, i, q.has_intervals) << "\n";
  if (q.has_intervals) out << pce_fixed_by_selection_note(ci);
}

void plot_qoi(const std::string& png, const PceQoiResult& q, const std::vector<std::string>& labels) {
  io::BarPlot plot;
  plot.title = q.name + ": Sobol' indices from PCE (" + std::to_string(q.runs_used) + " runs, Q2 " +
               fixed_text(q.expansion.validation.q2_loo) + ")" + (q.has_intervals ? ", bootstrap intervals" : "");
  plot.y_label = "index";
  plot.categories = labels;
  // Without intervals (bootstrap 0) the error bars collapse onto the bars.
  io::BarGroup s1{"S1 (first order)", to_vector(q.indices.S1), to_vector(q.indices.S1), to_vector(q.indices.S1)};
  io::BarGroup st{"ST (total)", to_vector(q.indices.ST), to_vector(q.indices.ST), to_vector(q.indices.ST)};
  if (q.has_intervals) {
    s1.lower = to_vector(q.intervals.S1_lower);
    s1.upper = to_vector(q.intervals.S1_upper);
    st.lower = to_vector(q.intervals.ST_lower);
    st.upper = to_vector(q.intervals.ST_upper);
  }
  plot.groups = {s1, st};
  io::write_png_or_warn(plot, png, "sensitivity", std::cerr);
}

void plot_channel(const std::string& png, const PceChannelResult& c, const std::vector<double>& t,
                  const std::vector<std::string>& labels, const std::string& command) {
  io::LinePlot plot;
  plot.title = c.name + ": first-order (solid) and total (dashed) indices along time, from PCE";
  plot.x_label = "t [s]";
  plot.y_label = "index";
  plot.y_range = io::AxisRange{-0.05, 1.05};
  for (Eigen::Index i = 0; i < c.indices.S1.cols(); ++i) {
    if (!(c.indices.aggregated_ST[i] > kPlottedTotalIndex)) continue;
    const std::string& name = labels[static_cast<std::size_t>(i)];
    plot.series.push_back({name + " S1", t, to_vector(c.indices.S1.col(i))});
    plot.series.push_back({name + " ST", t, to_vector(c.indices.ST.col(i)), io::SeriesStyle::dashed});
  }
  if (!plot.series.empty()) io::write_png_or_warn(plot, png, command, std::cerr);
}

}  // namespace

void write_pce_fixed_by_selection(io::Hdf5Writer& h5, const std::string& group, const PceSobolIntervals& intervals) {
  const auto flags = [](const std::vector<bool>& fixed) { return std::vector<int>(fixed.begin(), fixed.end()); };
  h5.write(group + "S1_fixed_by_selection", flags(intervals.fixed_by_selection.S1));
  h5.write(group + "ST_fixed_by_selection", flags(intervals.fixed_by_selection.ST));
}

bool pce_indices_not_to_trust(const PceSensitivityResult& result) {
  return std::any_of(result.qoi.begin(), result.qoi.end(), [](const PceQoiResult& q) {
    if (!q.fit_done) return false;  // a non-finite QoI: undefined, and said so
    if (!q.indices.defined) return !q.expansion.constant_output;
    return !surrogate_not_to_trust(q.name, q.expansion.validation).empty();
  });
}

std::string pce_interval_text(const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                              const std::vector<bool>& fixed, Eigen::Index i) {
  if (fixed[static_cast<std::size_t>(i)]) return kFixedBySelectionText;
  return "[" + fixed_text(lower[i]) + ", " + fixed_text(upper[i]) + "]";
}

std::string pce_fixed_by_selection_note(const PceSobolIntervals& intervals) {
  if (!intervals.fixed_by_selection.any()) return "";
  return std::string("  ") + kFixedBySelectionText +
         ": the selected terms make the index 0 or 1 whatever their coefficients; the bootstrap refits the "
         "coefficients only, so it cannot show how uncertain that selection is\n";
}

std::string pce_fixed_by_selection_warning(const std::string& qoi, const PceSobolIntervals& intervals,
                                           const std::vector<std::string>& labels, double q2_loo,
                                           double q2_threshold) {
  if (!intervals.fixed_by_selection.any() || q2_loo >= q2_threshold) return "";
  std::vector<std::string> fixed;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (intervals.fixed_by_selection.S1[i]) fixed.push_back("S1 " + labels[i]);
    if (intervals.fixed_by_selection.ST[i]) fixed.push_back("ST " + labels[i]);
  }
  return qoi + ": the selected terms fix " + comma_separated(fixed) + " at 0 or 1, and with Q2_LOO " +
         fixed_text(q2_loo, 4) + " below " + number_text(q2_threshold) +
         " that selection is itself uncertain: the bootstrap intervals, which refit the coefficients only, "
         "leave it out; the indices may be far from the model's: use more runs";
}

PceChannelResult pce_channel_indices(const std::string& name, const DesignMatrix& x_ok, const Eigen::MatrixXd& y_ok,
                                     const std::vector<Distribution>& inputs, const PceSensitivityOptions& options) {
  return channel_indices(name, x_ok, y_ok, inputs, options);
}

void write_pce_channel(io::Hdf5Writer& h5, const PceChannelResult& channel) { write_channel(h5, channel); }

void plot_pce_channel(const std::string& png, const PceChannelResult& channel, const std::vector<double>& t,
                      const std::vector<std::string>& labels, const std::string& command) {
  plot_channel(png, channel, t, labels, command);
}

namespace {

// A confidence the bootstrap's resamples cannot resolve is refused, naming both.
void refuse_unresolved_confidence(const io::JsonReader& r, const PceSensitivityOptions& o,
                                  const std::string& resamples_field) {
  if (o.bootstrap <= 0) return;
  if (const std::string problem =
          bootstrap_resolution_problem(o.confidence, "'confidence'", o.bootstrap, resamples_field, kMaxPceBootstrap);
      !problem.empty())
    r.fail("confidence", problem);
}

}  // namespace

PceSensitivityOptions parse_pce_options(const io::JsonReader& r, double confidence, std::uint64_t seed) {
  PceSensitivityOptions o;
  o.confidence = confidence;
  o.seed = seed;
  if (!r.has("pce")) {
    refuse_unresolved_confidence(r, o, "'pce.bootstrap' (by default)");
    return o;
  }
  const io::JsonReader p = r.child("pce");
  o.settings.max_degree = p.integer_or("max_degree", o.settings.max_degree, {1, kMaxPceDegree});
  o.settings.q_norm = p.number_or("q_norm", o.settings.q_norm);
  if (!(o.settings.q_norm > 0.0 && o.settings.q_norm <= 1.0)) p.fail("q_norm", "must lie in (0, 1]");
  const io::IntegerRange resamples{0, kMaxPceBootstrap,
                                   "0 (no intervals), or from " + std::to_string(kMinPceBootstrap) + " to " +
                                       std::to_string(kMaxPceBootstrap)};
  o.bootstrap = p.integer_or("bootstrap", o.bootstrap, resamples);
  if (o.bootstrap > 0 && o.bootstrap < kMinPceBootstrap) p.fail("bootstrap", io::whole_number_rule(resamples));
  refuse_unresolved_confidence(r, o, "'pce.bootstrap'");
  o.settings.q2_threshold = p.number_or("q2_threshold", o.settings.q2_threshold);
  if (!(o.settings.q2_threshold > 0.0 && o.settings.q2_threshold <= 1.0)) p.fail("q2_threshold", "must lie in (0, 1]");
  p.finish();
  return o;
}

int min_pce_sensitivity_runs(const StudySpec& spec, const PceSensitivityOptions& options) {
  return min_pce_runs(input_distributions(spec), options.settings);
}

PceQoiResult pce_qoi_indices(const std::string& name, const DesignMatrix& x_ok, const Eigen::VectorXd& y_ok,
                             const std::vector<Distribution>& inputs, const PceSensitivityOptions& options) {
  PceQoiResult q;
  q.name = name;
  q.runs_used = static_cast<int>(y_ok.size());
  q.undefined_reason = undefined_because_non_finite(y_ok);
  if (!q.undefined_reason.empty()) return q;
  try {
    PolynomialChaosSettings settings = options.settings;
    settings.stop = &InterruptGuard::flag();  // a signal ends the fit at its next step
    q.expansion = fit_polynomial_chaos(x_ok, y_ok, inputs, settings, name);
  } catch (const std::invalid_argument& e) {
    q.undefined_reason = e.what();
    return q;
  }
  q.fit_done = true;
  q.indices = pce_sobol_indices(q.expansion);
  if (q.expansion.constant_output) {
    q.indices.defined = false;
    q.undefined_reason = "the QoI is constant over the " + std::to_string(q.runs_used) + " runs (" +
                         fixed_text(y_ok.size() ? y_ok[0] : 0.0, 6) + "): no variance to apportion";
    return q;
  }
  if (!q.indices.defined) {  // the QoI varies, but no term beyond the constant was selected
    q.undefined_reason = "the QoI varies over the " + std::to_string(q.runs_used) +
                         " runs, but the expansion selected no term beyond the constant (Q2_LOO " +
                         fixed_text(q.expansion.validation.q2_loo, 4) + ", degree " +
                         std::to_string(q.expansion.degree) + "): no input explains its variance at this size; " +
                         "use more runs, or a higher pce.max_degree";
    return q;
  }
  if (options.bootstrap == 0) return q;
  try {
    q.intervals = bootstrap_pce_sobol(q.expansion, x_ok, y_ok,
                                      {options.bootstrap, options.confidence, options.seed, &InterruptGuard::flag()});
    // Percentiles of a few refits that happened to work are no interval.
    q.has_intervals = q.intervals.resamples_used >= kMinUsedResampleShare * options.bootstrap;
  } catch (const WorkStopped&) {
    throw;  // a signal: the study ends, its runs kept
  } catch (const std::runtime_error&) {
    // No resample could be refitted: the indices stand, without intervals (warned by the caller).
  }
  return q;
}

PceSensitivityResult analyse_pce_sensitivity(const StudySpec& spec, const PceSensitivityOptions& options,
                                             const DesignMatrix& x, const std::vector<RunRecord>& records) {
  const StudyModel& model = *spec.model;
  const RecordLayout layout = model.layout();
  const std::vector<Distribution> inputs = input_distributions(spec);
  const std::vector<Eigen::Index> ok = ok_runs(records);
  const DesignMatrix x_ok = rows_of(x, ok);
  const auto n_ok = static_cast<Eigen::Index>(ok.size());
  PceSensitivityResult out;
  out.runs_used = static_cast<int>(n_ok);
  for (int q = 0; q < layout.qoi_count; ++q) {
    Eigen::VectorXd y(n_ok);
    for (Eigen::Index k = 0; k < n_ok; ++k)
      y[k] = records[static_cast<std::size_t>(ok[static_cast<std::size_t>(k)])].qoi[static_cast<std::size_t>(q)];
    out.qoi.push_back(pce_qoi_indices(model.qoi_names()[static_cast<std::size_t>(q)], x_ok, y, inputs, options));
  }
  for (int c = 0; c < layout.channel_count; ++c) {
    Eigen::MatrixXd y(n_ok, layout.time_samples);
    for (Eigen::Index k = 0; k < n_ok; ++k) {
      const double* curve = records[static_cast<std::size_t>(ok[static_cast<std::size_t>(k)])].curve(c, layout.time_samples);
      for (int s = 0; s < layout.time_samples; ++s) y(k, s) = curve[s];
    }
    out.channels.push_back(
        pce_channel_indices(model.channel_names()[static_cast<std::size_t>(c)], x_ok, y, inputs, options));
  }
  for (const PceQoiResult& q : out.qoi) {
    if (!q.indices.defined) out.warnings.push_back(q.name + ": indices undefined: " + q.undefined_reason);
    else if (!q.expansion.validation.warning.empty()) out.warnings.push_back(q.expansion.validation.warning);
    if (const std::string distrust = q.indices.defined ? surrogate_not_to_trust(q.name, q.expansion.validation) : "";
        !distrust.empty())
      out.warnings.push_back(distrust + " (exit status 2)");
    if (q.has_intervals)
      if (const std::string w = pce_fixed_by_selection_warning(q.name, q.intervals, input_labels(spec),
                                                                q.expansion.validation.q2_loo,
                                                                options.settings.q2_threshold);
          !w.empty())
        out.warnings.push_back(w);
    if (q.indices.defined && options.bootstrap > 0 && !q.has_intervals)
      out.warnings.push_back(q.name + ": " + std::to_string(q.intervals.resamples_used) + " of " +
                             std::to_string(options.bootstrap) + " bootstrap resamples could be refitted (the " +
                             std::to_string(q.runs_used) + " runs hold too few distinct points for the " +
                             std::to_string(q.expansion.multi_indices.size()) +
                             "-term expansion); no intervals: use more runs");
  }
  for (const PceChannelResult& c : out.channels) {
    if (!c.defined) out.warnings.push_back(c.name + ": indices along time undefined: " + c.undefined_reason);
    else if (!c.curves.warning.empty()) out.warnings.push_back(c.curves.warning);
  }
  return out;
}

void write_pce_sensitivity(io::Hdf5Writer& h5, const StudySpec& spec, const PceSensitivityOptions& options,
                           const PceSensitivityResult& result) {
  h5.attribute("/", "pce_max_degree", static_cast<long long>(options.settings.max_degree));
  h5.attribute("/", "pce_q_norm", options.settings.q_norm);
  h5.attribute("/", "pce_q2_threshold", options.settings.q2_threshold);
  h5.attribute("/", "runs_used", static_cast<long long>(result.runs_used));
  std::vector<std::string> undefined;
  for (const PceQoiResult& q : result.qoi) {
    write_qoi(h5, q, options);
    if (!q.indices.defined) undefined.push_back(q.name);
  }
  write_undefined_indices(h5, undefined);
  if (!result.channels.empty()) h5.write("/t", spec.model->time_s());
  for (const PceChannelResult& c : result.channels) write_channel(h5, c);
}

void print_pce_sensitivity(std::ostream& out, const StudySpec& spec, const PceSensitivityOptions& options,
                           const PceSensitivityResult& result) {
  const std::vector<std::string> labels = input_labels(spec);
  for (const PceQoiResult& q : result.qoi) print_qoi(out, q, labels, options.confidence);
  for (const PceChannelResult& c : result.channels) {
    if (!c.defined) continue;
    out << c.name << " along time (PCE, " << c.curves.multi_indices.size() << " shared terms, min Q2_LOO "
        << fixed_text(c.curves.q2_loo.minCoeff(), 4) << "), variance-weighted: ";
    for (Eigen::Index i = 0; i < c.indices.aggregated_ST.size(); ++i)
      out << labels[static_cast<std::size_t>(i)] << " S1 " << fixed_text(c.indices.aggregated_S1[i]) << " ST "
          << fixed_text(c.indices.aggregated_ST[i]) << (i + 1 < c.indices.aggregated_ST.size() ? "; " : "\n");
  }
}

namespace {

// The file names of the figures, shared by plot_pce_sensitivity and pce_sensitivity_figures.
std::string pce_qoi_suffix(const std::string& qoi) { return "_pce_" + qoi + ".png"; }
std::string pce_channel_suffix(const std::string& channel) { return "_pce_t_" + channel + ".png"; }

}  // namespace

std::vector<PlannedFigure> pce_sensitivity_figures(const StudySpec& spec, std::vector<PlannedFigure> figures) {
  for (const std::string& q : spec.model->qoi_names()) figures.push_back({pce_qoi_suffix(q), "QoI '" + q + "'"});
  for (const std::string& c : spec.model->channel_names())
    figures.push_back({pce_channel_suffix(c), "channel '" + c + "' (its indices along time)"});
  return figures;
}

void plot_pce_sensitivity(const std::string& results_path, const StudySpec& spec,
                          const PceSensitivityResult& result) {
  const std::vector<std::string> labels = input_labels(spec);
  for (const PceQoiResult& q : result.qoi)
    if (q.indices.defined) plot_qoi(sibling_path(results_path, pce_qoi_suffix(q.name)), q, labels);
  for (const PceChannelResult& c : result.channels)
    if (c.defined)
      plot_channel(sibling_path(results_path, pce_channel_suffix(c.name)), c, spec.model->time_s(), labels,
                   "sensitivity");
}

}  // namespace rover::study
