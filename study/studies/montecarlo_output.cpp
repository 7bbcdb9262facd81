// The Monte Carlo study's result file and console report (montecarlo.hpp;
// the HDF5 layout is docs/results_format.md, "montecarlo").
#include <ostream>

#include "study/studies/report_format.hpp"
#include "study/studies/montecarlo.hpp"
#include "study/studies/study_output.hpp"

namespace rover::study {
namespace {

void write_summary(io::Hdf5Writer& h5, const std::string& name, const QoiSummary& s, double confidence) {
  const std::string g = "/summary/" + name + "/";
  h5.write(g + "mean", std::vector<double>{s.mean, s.mean_lower, s.mean_upper});
  h5.write(g + "sd", std::vector<double>{s.sd, s.sd_lower, s.sd_upper});
  std::vector<double> p, v, lo, hi;
  for (const QuantileEstimate& e : s.quantiles) {
    p.push_back(e.probability);
    v.push_back(e.value);
    lo.push_back(e.lower);
    hi.push_back(e.upper);
  }
  h5.write(g + "quantile_probability", p);
  h5.write(g + "quantile", v);
  h5.write(g + "quantile_lower", lo);
  h5.write(g + "quantile_upper", hi);
  h5.attribute(g + "mean", "columns", "estimate, lower, upper (Student t)");
  h5.attribute(g + "sd", "columns",
               s.sd_interval_chi_square ? "estimate, lower, upper (chi-square, normal values assumed)"
                                        : "estimate, lower, upper (bootstrap percentile)");
  h5.attribute(g + "quantile", "note", s.note);
  h5.attribute(g + "mean", "samples", static_cast<long long>(s.samples));
  h5.attribute(g + "mean", "confidence", confidence);
}

void write_band(io::Hdf5Writer& h5, const std::string& channel, const Band& b) {
  const std::string g = "/bands/" + channel + "/";
  h5.write(g + "mean", b.mean);
  h5.write(g + "std", b.std);
  h5.write(g + "lower", b.lower);
  h5.write(g + "upper", b.upper);
  h5.write(g + "p00135", b.p00135);
  h5.write(g + "p99865", b.p99865);
  h5.attribute(g + "mean", "samples_used", static_cast<long long>(b.samples_used));
}

// Why the intervals of a small sample are the normal-theory ones.
std::string small_sample_note(int samples) {
  return "the sd's interval is the chi-square one of normal values, as the mean's Student t is: " +
         std::to_string(samples) + " runs are too few for a bootstrap of the sd (it needs " +
         std::to_string(kMinBootstrapSdSamples) + ") or for the central limit theorem";
}

std::string join_notes(const std::string& a, const std::string& b) { return a.empty() || b.empty() ? a + b : a + "; " + b; }

}  // namespace

void write_montecarlo(const MonteCarloResult& result, io::Hdf5Writer& h5) {
  const StudySpec& spec = result.study.spec;
  const StudyModel& model = *spec.model;
  write_study_inputs(h5, spec, result.inputs);
  h5.write("/t", model.time_s());
  for (std::size_t q = 0; q < result.qoi.size(); ++q) {
    const std::string& name = model.qoi_names()[q];
    h5.write("/qoi/" + name, result.qoi[q]);
    h5.attribute("/qoi/" + name, "unit", model.qoi_units()[q]);
    write_summary(h5, name, result.summaries[q], result.study.confidence);
  }
  if (spec.rover) write_qoi_definitions(h5, spec.rover->qois());
  for (std::size_t c = 0; c < result.bands.size(); ++c) write_band(h5, model.channel_names()[c], result.bands[c]);
  h5.write("/samples/status", result.status);
  h5.write("/samples/message", result.messages);
  h5.write("/samples/wall_time_s", result.wall_time_s);
  h5.write("/samples/rhs_evaluations", result.rhs_evaluations);
  h5.attribute("/", "failed_samples", static_cast<long long>(result.failed));
  h5.attribute("/", "confidence", result.study.confidence);
}

void report_montecarlo(const MonteCarloResult& result, std::ostream& out) {
  const StudyModel& model = *result.study.spec.model;
  const std::string percent = percent_digits(result.study.confidence);
  std::string last_note;
  const bool sd_interval = result.study.bootstrap_resamples > 0;
  for (std::size_t q = 0; q < result.summaries.size(); ++q) {
    const QoiSummary& s = result.summaries[q];
    const DisplayUnit unit = display_unit(model.qoi_units()[q]);
    const double k = unit.factor;
    out << "  " << model.qoi_names()[q] << ": ";
    if (s.samples == 0) {
      out << "undefined: no run gave a finite value\n";
    } else if (s.samples < 2) {  // a mean without an interval, and no sd
      out << "mean " << k * s.mean << " " << unit.name << "; sd and intervals undefined: 1 run succeeded, they need 2\n";
    } else {
      out << "mean " << k * s.mean << " [" << k * s.mean_lower << ", " << k * s.mean_upper << "], sd " << k * s.sd;
      if (sd_interval) out << " [" << k * s.sd_lower << ", " << k * s.sd_upper << "]";
      out << " " << unit.name << " (" << s.samples << " runs, " << percent << " % intervals"
          << (sd_interval ? "" : "; no sd interval: \"bootstrap\": 0") << ")\n";
    }
    const std::string note = s.sd_interval_chi_square ? join_notes(small_sample_note(s.samples), s.note) : s.note;
    if (!note.empty() && note != last_note) out << "    " << note << "\n";
    last_note = note;
  }
}

}  // namespace rover::study
