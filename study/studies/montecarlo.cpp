// See montecarlo.hpp.
#include "study/studies/montecarlo.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "io/hdf5_file.hpp"
#include "io/plot.hpp"
#include "study/studies/study_output.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::study {
namespace {

constexpr double kTailProbabilities[] = {0.00135, 0.5, 0.99865};

std::vector<double> scaled(const std::vector<double>& v, double factor) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), [&](double x) { return factor * x; });
  return out;
}

// Plot lengths in mm, everything else in its own unit.
double display_factor(const std::string& unit) { return unit == "m" ? 1000.0 : 1.0; }
std::string display_unit(const std::string& unit) { return unit == "m" ? "mm" : unit; }

void plot_band(const std::string& png, const std::string& title, const std::string& channel,
               const std::string& unit, const std::vector<double>& t, const Band& band) {
  const double k = display_factor(unit);
  io::LinePlot plot;
  plot.title = title + ": " + channel + ", " + std::to_string(band.samples_used) + " runs";
  plot.x_label = "t [s]";
  plot.y_label = channel + " [" + display_unit(unit) + "]";
  plot.bands.push_back({"mean -+ 3 sd", t, scaled(band.lower, k), scaled(band.upper, k)});
  plot.series.push_back({"mean", t, scaled(band.mean, k)});
  plot.series.push_back({"0.135 % quantile", t, scaled(band.p00135, k), io::SeriesStyle::dashed});
  plot.series.push_back({"99.865 % quantile", t, scaled(band.p99865, k), io::SeriesStyle::dashed});
  io::write_png_or_warn(plot, png, "montecarlo", std::cerr);
}

// A histogram drawn as its outline, with the mean and its interval marked.
void plot_histogram(const std::string& png, const std::string& name, const std::string& unit,
                    const std::vector<double>& values, const QoiSummary& summary) {
  std::vector<double> v;
  for (double x : values)
    if (std::isfinite(x)) v.push_back(x * display_factor(unit));
  if (v.size() < 2) return;
  const auto [lo_it, hi_it] = std::minmax_element(v.begin(), v.end());
  const double lo = *lo_it, hi = *hi_it;
  const int bins = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(v.size()))), 5, 60);
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
  plot.title = name + ": " + std::to_string(v.size()) + " runs, mean " +
               std::to_string(summary.mean * display_factor(unit)) + " " + display_unit(unit);
  plot.x_label = name + " [" + display_unit(unit) + "]";
  plot.y_label = "runs per bin";
  plot.series.push_back(outline);
  const double peak = *std::max_element(counts.begin(), counts.end());
  for (const auto& [label, x] : {std::pair{"mean", summary.mean}, std::pair{"mean, lower 95 %", summary.mean_lower},
                                 std::pair{"mean, upper 95 %", summary.mean_upper}}) {
    if (!std::isfinite(x)) continue;
    const double xd = x * display_factor(unit);
    plot.series.push_back({label, {xd, xd}, {0.0, peak}, io::SeriesStyle::dashed});
  }
  io::write_png_or_warn(plot, png, "montecarlo", std::cerr);
}

// Running mean and sd of a QoI against N with their 95 % intervals (normal
// theory, at log-spaced N): how far the estimates have settled.
void plot_convergence(const std::string& png, const std::string& name, const std::string& unit,
                      const std::vector<double>& values) {
  const double k = display_factor(unit);
  io::Series mean{"mean"}, sd{"sd"};
  io::Band mean_band{"mean, 95 %"}, sd_band{"sd, 95 %"};
  double m = 0.0, s2 = 0.0;
  int n = 0;
  double next = 4.0;
  for (double x : values) {
    if (!std::isfinite(x)) continue;
    ++n;
    const double delta = x - m;
    m += delta / n;
    s2 += delta * (x - m);
    if (n >= static_cast<int>(next) || n == static_cast<int>(values.size())) {
      next *= 1.25;
      const double sd_n = std::sqrt(s2 / std::max(1, n - 1));
      const double half = 1.96 * sd_n / std::sqrt(static_cast<double>(n));
      mean.x.push_back(n);
      mean.y.push_back(k * m);
      mean_band.x.push_back(n);
      mean_band.lower.push_back(k * (m - half));
      mean_band.upper.push_back(k * (m + half));
      const double sd_half = 1.96 * sd_n / std::sqrt(2.0 * std::max(1, n - 1));
      sd.x.push_back(n);
      sd.y.push_back(k * sd_n);
      sd_band.x.push_back(n);
      sd_band.lower.push_back(k * (sd_n - sd_half));
      sd_band.upper.push_back(k * (sd_n + sd_half));
    }
  }
  if (mean.x.size() < 2) return;
  for (auto [series, band, what] : {std::tuple{&mean, &mean_band, "mean"}, std::tuple{&sd, &sd_band, "sd"}}) {
    io::LinePlot plot;
    plot.title = name + ": running " + std::string(what) + " against N";
    plot.x_label = "N";
    plot.y_label = name + " " + what + " [" + display_unit(unit) + "]";
    plot.log_x = true;
    plot.series.push_back(*series);
    plot.bands.push_back(*band);
    io::write_png_or_warn(plot, sibling_path(png, std::string("_") + what + ".png"), "montecarlo", std::cerr);
  }
}

}  // namespace

MonteCarloStudy load_montecarlo_study(const std::string& path) {
  const io::Json json = io::read_json_file(path);
  const io::JsonReader r(json, path);
  MonteCarloStudy s;
  s.spec = parse_study_spec(r, {"montecarlo"});
  if (r.has("confidence")) {
    s.confidence = r.number("confidence");
    if (!(s.confidence > 0.5 && s.confidence < 1.0)) r.fail("confidence", "must lie in (0.5, 1)");
  }
  if (r.has("bootstrap")) {
    s.bootstrap_resamples = r.integer("bootstrap");
    if (s.bootstrap_resamples < 100 || s.bootstrap_resamples > 100000)
      r.fail("bootstrap", "give 100 .. 100000 resamples");
  }
  if (s.spec.rover && s.spec.rover->qoi_names().empty() && s.spec.rover->channel_names().empty())
    r.fail("qoi", "a Monte Carlo needs at least one of \"qoi\" and \"channels\"");
  r.finish();
  return s;
}

MonteCarloAnalysis::MonteCarloAnalysis(const RecordLayout& layout, int samples, double confidence,
                                       int bootstrap_resamples, std::uint64_t seed)
    : layout_(layout), confidence_(confidence), bootstrap_resamples_(bootstrap_resamples), seed_(seed) {
  result_.qoi.resize(static_cast<std::size_t>(layout.qoi_count));
  for (auto& q : result_.qoi) q.reserve(static_cast<std::size_t>(samples));
  for (int c = 0; c < layout.channel_count; ++c)
    bands_.emplace_back(static_cast<std::size_t>(layout.time_samples), static_cast<std::size_t>(samples));
}

void MonteCarloAnalysis::add(const RunRecord& r) {
  ++result_.samples;
  result_.failed += r.ok() ? 0 : 1;
  for (int q = 0; q < layout_.qoi_count; ++q)
    result_.qoi[static_cast<std::size_t>(q)].push_back(r.ok() ? r.qoi[static_cast<std::size_t>(q)] : std::nan(""));
  if (r.ok())
    for (int c = 0; c < layout_.channel_count; ++c)
      bands_[static_cast<std::size_t>(c)].add(r.curve(c, layout_.time_samples));
  result_.status.push_back(r.status);
  result_.messages.push_back(r.message);
  result_.wall_time_s.push_back(r.wall_time_s);
  result_.rhs_evaluations.push_back(r.rhs_evaluations);
}

MonteCarloResult MonteCarloAnalysis::finish() const {
  MonteCarloResult out = result_;
  const std::vector<double> probabilities(std::begin(kTailProbabilities), std::end(kTailProbabilities));
  for (const auto& values : out.qoi)
    out.summaries.push_back(summarize_qoi(values, probabilities, confidence_, bootstrap_resamples_, seed_));
  for (const StreamingBand& b : bands_) out.bands.push_back(b.result());
  return out;
}

std::string run_montecarlo(const MonteCarloStudy& study, const StudyRunControl& control) {
  const StudySpec& spec = study.spec;
  const StudyModel& model = *spec.model;
  const bool root = world_rank() == 0;
  const std::string out = checked_results_path(spec.name, control.results_path);
  const RecordLayout layout = model.layout();
  const int N = spec.design.samples;
  // The design on every rank; the QoIs, statuses and band heaps on rank 0.
  require_memory("design and per-run results (N = " + std::to_string(N) + ")",
                 8.0 * N * (static_cast<double>(spec.inputs.size()) + layout.qoi_count + 4));
  const DesignMatrix x = study_design(spec);
  const auto T = static_cast<std::size_t>(layout.time_samples);

  std::unique_ptr<io::Hdf5Writer> h5;
  if (root) {
    h5 = std::make_unique<io::Hdf5Writer>(out);
    for (const std::string& c : model.channel_names())
      h5->create_matrix("/curves/" + c, static_cast<std::size_t>(N), T, std::nan(""));
  }
  MonteCarloAnalysis analysis(layout, N, study.confidence, study.bootstrap_resamples, spec.design.seed);
  auto compute = [&](int i) { return encode_record(i, model.run(x.row(i).data())); };
  auto consume = [&](TaskResult&& task) {
    const int index = task.index;
    const RunRecord record = decode_record(layout, std::move(task));
    if (record.ok())
      for (int c = 0; c < layout.channel_count; ++c)
        h5->write_row("/curves/" + model.channel_names()[static_cast<std::size_t>(c)],
                      static_cast<std::size_t>(index), record.curve(c, layout.time_samples), T);
    analysis.add(record);
  };
  StudyRunOptions options{out, spec.fingerprint, control.resume, "montecarlo", control.progress_interval_s,
                          control.resume_command, control.checkpoint};
  stream_study_tasks(N, compute, consume, options);
  if (!root) return out;

  const MonteCarloResult result = analysis.finish();
  const bool every_run_failed = result.failed == result.samples;
  const std::string first_failure = result.messages.empty() ? "" : result.messages[0];
  if (every_run_failed && std::filesystem::exists(out))  // status 1 never replaces an earlier result
    throw std::runtime_error("every run failed (first: " + first_failure + "); nothing was written, " + out +
                             " is unchanged; the runs are kept in " + io::ResultCheckpoint::path_for(out));
  write_study_provenance(*h5, spec, spec.fingerprint);
  write_study_inputs(*h5, spec, x);
  h5->write("/t", model.time_s());
  for (std::size_t q = 0; q < result.qoi.size(); ++q) {
    const std::string& name = model.qoi_names()[q];
    h5->write("/qoi/" + name, result.qoi[q]);
    h5->attribute("/qoi/" + name, "unit", model.qoi_units()[q]);
    const QoiSummary& s = result.summaries[q];
    const std::string g = "/summary/" + name + "/";
    h5->write(g + "mean", std::vector<double>{s.mean, s.mean_lower, s.mean_upper});
    h5->write(g + "sd", std::vector<double>{s.sd, s.sd_lower, s.sd_upper});
    std::vector<double> p, v, lo, hi;
    for (const QuantileEstimate& e : s.quantiles) {
      p.push_back(e.probability);
      v.push_back(e.value);
      lo.push_back(e.lower);
      hi.push_back(e.upper);
    }
    h5->write(g + "quantile_probability", p);
    h5->write(g + "quantile", v);
    h5->write(g + "quantile_lower", lo);
    h5->write(g + "quantile_upper", hi);
    h5->attribute(g + "mean", "columns", "estimate, lower, upper (Student t)");
    h5->attribute(g + "sd", "columns", "estimate, lower, upper (bootstrap percentile)");
    h5->attribute(g + "quantile", "note", s.note);
    h5->attribute(g + "mean", "samples", static_cast<long long>(s.samples));
    h5->attribute(g + "mean", "confidence", study.confidence);
  }
  for (std::size_t c = 0; c < result.bands.size(); ++c) {
    const Band& b = result.bands[c];
    const std::string g = "/bands/" + model.channel_names()[c] + "/";
    h5->write(g + "mean", b.mean);
    h5->write(g + "std", b.std);
    h5->write(g + "lower", b.lower);
    h5->write(g + "upper", b.upper);
    h5->write(g + "p00135", b.p00135);
    h5->write(g + "p99865", b.p99865);
    h5->attribute(g + "mean", "samples_used", static_cast<long long>(b.samples_used));
  }
  h5->write("/samples/status", result.status);
  h5->write("/samples/message", result.messages);
  h5->write("/samples/wall_time_s", result.wall_time_s);
  h5->write("/samples/rhs_evaluations", result.rhs_evaluations);
  h5->attribute("/", "failed_samples", static_cast<long long>(result.failed));
  h5->attribute("/", "confidence", study.confidence);
  h5->commit();
  remove_checkpoint(out);

  std::cerr << "montecarlo: " << N << " runs (" << result.failed << " failed), wrote " << out << "\n";
  std::string last_note;
  for (std::size_t q = 0; q < result.summaries.size(); ++q) {
    const QoiSummary& s = result.summaries[q];
    const std::string unit = model.qoi_units()[q];
    const double k = display_factor(unit);
    std::cerr << "  " << model.qoi_names()[q] << ": mean " << k * s.mean << " [" << k * s.mean_lower << ", "
              << k * s.mean_upper << "], sd " << k * s.sd << " [" << k * s.sd_lower << ", " << k * s.sd_upper
              << "] " << display_unit(unit) << " (" << s.samples << " runs, "
              << static_cast<int>(100 * study.confidence) << " % intervals)\n";
    if (!s.note.empty() && s.note != last_note) std::cerr << "    " << s.note << "\n";
    last_note = s.note;
  }
  if (every_run_failed)
    throw std::runtime_error("every run failed (first: " + first_failure + "); the results are in " + out);
  if (control.plot) {
    for (std::size_t c = 0; c < result.bands.size(); ++c) {
      const std::string& name = model.channel_names()[c];
      plot_band(sibling_path(out, "_band_" + name + ".png"), spec.name, name,
                channel_unit(channel_from_name(name)), model.time_s(), result.bands[c]);
    }
    for (std::size_t q = 0; q < result.qoi.size(); ++q) {
      const std::string& name = model.qoi_names()[q];
      plot_histogram(sibling_path(out, "_hist_" + name + ".png"), name, model.qoi_units()[q], result.qoi[q],
                     result.summaries[q]);
      plot_convergence(sibling_path(out, "_convergence_" + name + ".png"), name, model.qoi_units()[q],
                       result.qoi[q]);
    }
  }
  return out;
}

}  // namespace rover::study
