// The sensitivity study's result file and console report (sensitivity.hpp;
// docs/results_format.md, "sensitivity").
#include <algorithm>
#include <iomanip>
#include <numeric>
#include <ostream>

#include "study/studies/report_format.hpp"
#include "study/studies/sensitivity.hpp"
#include "study/studies/study_output.hpp"

namespace rover::study {
namespace {


// The group of a QoI without indices: attributes defined = 0 and
// undefined_reason.
void write_undefined(io::Hdf5Writer& h5, const std::string& group, const std::string& reason) {
  h5.create_group(group);
  h5.attribute(group, "defined", 0LL);
  h5.attribute(group, "undefined_reason", reason);
}

const std::string* undefined_reason(const SensitivityResult& result, const std::string& qoi) {
  for (const UndefinedIndices& u : result.undefined)
    if (u.qoi == qoi) return &u.reason;
  return nullptr;
}

void write_sobol(io::Hdf5Writer& h5, const std::string& qoi, const SobolIndices& s, const SobolOptions& options) {
  const std::string g = "/indices/" + qoi + "/";
  h5.write(g + "S1", to_vector(s.S1));
  h5.write(g + "ST", to_vector(s.ST));
  h5.write(g + "S1_lower", to_vector(s.S1_lower));
  h5.write(g + "S1_upper", to_vector(s.S1_upper));
  h5.write(g + "ST_lower", to_vector(s.ST_lower));
  h5.write(g + "ST_upper", to_vector(s.ST_upper));
  h5.write(g + "mean", std::vector<double>{s.mean});
  h5.write(g + "variance", std::vector<double>{s.variance});
  if (s.S2.size()) {
    h5.write(g + "S2", s.S2);
    h5.write(g + "S2_lower", s.S2_lower);
    h5.write(g + "S2_upper", s.S2_upper);
  }
  h5.attribute(g + "S1", "groups_used", static_cast<long long>(s.groups_used));
  h5.attribute(g + "S1", "groups_total", static_cast<long long>(s.groups_total));
  h5.attribute(g + "S1", "confidence", options.confidence);
  h5.attribute(g + "S1", "bootstrap_resamples", static_cast<long long>(options.bootstrap_resamples));
}

void write_sobol_t(io::Hdf5Writer& h5, const std::string& channel, const SobolIndicesAlongTime& s) {
  h5.write("/indices_t/" + channel + "/S1", s.S1);
  h5.write("/indices_t/" + channel + "/ST", s.ST);
  h5.write("/indices_t/" + channel + "/variance", to_vector(s.variance));
  h5.attribute("/indices_t/" + channel + "/S1", "undefined_times", undefined_time_count(s));
  h5.attribute("/indices_t/" + channel + "/S1", "undefined_meaning",
               std::string("times at which S1 and ST are NaN: every run has the same value there (variance 0)"));
  h5.write("/aggregated/" + channel + "/S1", to_vector(s.aggregated_S1));
  h5.write("/aggregated/" + channel + "/ST", to_vector(s.aggregated_ST));
}

void write_morris(io::Hdf5Writer& h5, const std::string& qoi, const MorrisResult& m) {
  const std::string g = "/morris/" + qoi + "/";
  h5.write(g + "mu", to_vector(m.mu));
  h5.write(g + "mu_star", to_vector(m.mu_star));
  h5.write(g + "sigma", to_vector(m.sigma));
  h5.write(g + "mu_star_lower", to_vector(m.mu_star_lower));
  h5.write(g + "mu_star_upper", to_vector(m.mu_star_upper));
  h5.write(g + "ranking", m.ranking);
  h5.attribute(g + "mu", "trajectories_used", static_cast<long long>(m.trajectories_used));
}

// " [lower, upper]", or nothing when there are no intervals ("bootstrap": 0).
std::string interval_text(bool intervals, double lower, double upper) {
  return intervals ? " [" + fixed_text(lower) + ", " + fixed_text(upper) + "]" : "";
}

void print_sobol(std::ostream& out, const std::string& qoi, const SobolIndices& s,
                 const std::vector<std::string>& labels, double confidence, bool intervals) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(s.ST.size()));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return s.ST[a] > s.ST[b]; });
  const std::string too_few_groups = "no intervals: " + std::to_string(s.groups_used) +
                                     " groups are too few to resample (at least " +
                                     std::to_string(kMinBootstrapSobolGroups) + ")";
  out << qoi << " (mean " << s.mean << ", variance " << s.variance << ", " << s.groups_used << " of "
      << s.groups_total << " groups; "
      << (!intervals ? std::string("no intervals: \"bootstrap\": 0")
                     : s.has_intervals ? percent_digits(confidence) + " % intervals" : too_few_groups)
      << "), by total index:\n";
  intervals = intervals && s.has_intervals;
  for (Eigen::Index i : order)
    out << "  " << std::left << std::setw(kIndexLabelWidth) << labels[static_cast<std::size_t>(i)] << std::right
        << " S1 " << std::setw(6) << fixed_text(s.S1[i]) << interval_text(intervals, s.S1_lower[i], s.S1_upper[i])
        << "   ST " << std::setw(6) << fixed_text(s.ST[i]) << interval_text(intervals, s.ST_lower[i], s.ST_upper[i])
        << "\n";
}

void print_morris(std::ostream& out, const std::string& qoi, const MorrisResult& m,
                  const std::vector<std::string>& labels, bool intervals) {
  out << qoi << " (Morris, " << m.trajectories_used << " trajectories";
  if (intervals && !m.has_intervals)
    out << "; no intervals: " << m.trajectories_used << " trajectories are too few to resample (at least "
        << kMinBootstrapMorrisTrajectories << ")";
  out << "), by mu*:\n";
  intervals = intervals && m.has_intervals;
  for (int i : m.ranking) {
    out << "  " << std::left << std::setw(kIndexLabelWidth) << labels[static_cast<std::size_t>(i)] << std::right
        << " mu* " << std::setw(10) << m.mu_star[i];
    if (intervals) out << " [" << m.mu_star_lower[i] << ", " << m.mu_star_upper[i] << "]";
    out << "  mu " << std::setw(10) << m.mu[i] << "  sigma " << m.sigma[i] << "\n";
  }
}

void print_aggregated(std::ostream& out, const std::string& channel, const SobolIndicesAlongTime& s,
                      const std::vector<std::string>& labels) {
  out << channel << " along time, variance-weighted: ";
  for (Eigen::Index i = 0; i < s.aggregated_ST.size(); ++i)
    out << labels[static_cast<std::size_t>(i)] << " S1 " << fixed_text(s.aggregated_S1[i]) << " ST "
        << fixed_text(s.aggregated_ST[i]) << (i + 1 < s.aggregated_ST.size() ? "; " : "\n");
}

}  // namespace

void write_sensitivity(const SensitivityResult& result, io::Hdf5Writer& h5) {
  const SensitivityStudy& study = result.study;
  const StudyModel& model = *study.spec.model;
  write_study_inputs(h5, study.spec, result.inputs);
  h5.attribute("/", "method", sensitivity_method_name(study.method));
  h5.attribute("/", "runs", static_cast<long long>(result.inputs.rows()));
  h5.attribute("/", "failed_runs", static_cast<long long>(result.failed_runs));
  h5.attribute("/", "runs_wall_time_s", result.runs_wall_time_s);
  h5.attribute("/", "analysis_wall_time_s", result.analysis_wall_time_s);
  for (std::size_t q = 0; q < result.qoi.size(); ++q) h5.write("/qoi/" + model.qoi_names()[q], result.qoi[q]);
  if (study.spec.rover) write_qoi_definitions(h5, study.spec.rover->qois());
  h5.write("/samples/status", result.status);
  h5.write("/samples/message", result.messages);
  for (std::size_t q = 0; q < result.sobol.size(); ++q) {
    const std::string& name = model.qoi_names()[q];
    if (const std::string* why = undefined_reason(result, name)) write_undefined(h5, "/indices/" + name, *why);
    else write_sobol(h5, name, result.sobol[q], study.sobol);
  }
  if (!result.sobol_t.empty()) h5.write("/t", model.time_s());
  for (std::size_t c = 0; c < result.sobol_t.size(); ++c) {
    const std::string& channel = model.channel_names()[c];
    write_sobol_t(h5, channel, result.sobol_t[c]);
    if (const std::string* why = undefined_reason(result, channel)) write_undefined(h5, "/indices_t/" + channel, *why);
  }
  for (std::size_t q = 0; q < result.morris.size(); ++q) {
    const std::string& name = model.qoi_names()[q];
    if (const std::string* why = undefined_reason(result, name)) write_undefined(h5, "/morris/" + name, *why);
    else write_morris(h5, name, result.morris[q]);
  }
  std::vector<std::string> undefined;
  for (const UndefinedIndices& u : result.undefined) undefined.push_back(u.qoi);
  write_undefined_indices(h5, undefined);
  if (study.method == SensitivityMethod::kPce) write_pce_sensitivity(h5, study.spec, study.pce, result.pce);
}

void report_sensitivity(const SensitivityResult& result, std::ostream& out) {
  const SensitivityStudy& study = result.study;
  const StudyModel& model = *study.spec.model;
  const std::vector<std::string> labels = input_labels(study.spec);
  out << "  runs " << fixed_text(result.runs_wall_time_s, 1) << " s, analysis "
      << fixed_text(result.analysis_wall_time_s, 2) << " s\n";
  if (!result.failure_report.empty()) out << "  " << result.failure_report << "\n";
  for (std::size_t q = 0; q < result.sobol.size(); ++q)
    if (!undefined_reason(result, model.qoi_names()[q]))
      print_sobol(out, model.qoi_names()[q], result.sobol[q], labels, study.sobol.confidence,
                  study.sobol.bootstrap_resamples > 0);
  if (study.method == SensitivityMethod::kPce) print_pce_sensitivity(out, study.spec, study.pce, result.pce);
  for (std::size_t q = 0; q < result.morris.size(); ++q)
    if (!undefined_reason(result, model.qoi_names()[q]))
      print_morris(out, model.qoi_names()[q], result.morris[q], labels, study.morris.bootstrap_resamples > 0);
  for (std::size_t c = 0; c < result.sobol_t.size(); ++c)
    if (!undefined_reason(result, model.channel_names()[c]))
      print_aggregated(out, model.channel_names()[c], result.sobol_t[c], labels);
  for (const std::string& w : result.warnings) out << "sensitivity: warning: " << w << "\n";
  if (no_index_for_want_of_runs(result))
    out << "sensitivity: error: no QoI or channel has indices: too few whole groups (trajectories) came through "
           "the failed runs (the warnings above say which); the file holds the runs, but no index to use\n";
}

}  // namespace rover::study
