// See montecarlo.hpp: the study's configuration, analysis and runs.
#include "study/studies/montecarlo.hpp"
#include "study/estimators/bootstrap_resolution.hpp"

#include <cmath>

#include "study/runtime/study_runner.hpp"
#include "study/studies/study_output.hpp"
#include "io/config_kind.hpp"

namespace rover::study {
namespace {

constexpr double kTailProbabilities[] = {0.00135, 0.5, 0.99865};

// The accepted ranges of the study file's keys.
constexpr double kMinConfidence = 0.5, kMaxConfidence = 1.0;  // exclusive
constexpr int kMinBootstrap = 100, kMaxBootstrap = 100000;
constexpr int kNoSdInterval = 0;  // "bootstrap": 0

// Per sample, beyond the design, QoIs, status and message: the wall time, the
// rhs evaluations.
constexpr double kPerSampleValues = 2.0;
// The fewest samples with a standard deviation (and so a band).
constexpr int kMinSamples = 2;

}  // namespace

namespace {

// --samples and --seed replace the file's design before it is checked; both
// are settings of the runs' key, wherever their value came from.
void apply_design_overrides(const DesignOverrides& o, StudySpec& spec) {
  DesignSpec& design = spec.design;
  if (o.samples) {
    if (design.type == DesignType::kGrid)
      throw std::invalid_argument("--samples does not apply to a grid design (its size is the product of its levels)");
    design.samples = static_cast<int>(*o.samples);
  }
  if (o.seed) {
    if (design.type == DesignType::kGrid)
      throw std::invalid_argument("--seed does not apply to a grid design (its points are its levels, not drawn)");
    design.seed = *o.seed;
  }
  spec.fingerprint = with_setting(spec.fingerprint, "--samples", std::to_string(design.samples), o.samples.has_value());
  spec.fingerprint = with_setting(spec.fingerprint, "--seed", std::to_string(design.seed), o.seed.has_value());
}

}  // namespace

MonteCarloStudy load_montecarlo_study(const std::string& path, const DesignOverrides& overrides) {
  const io::Json json = io::read_config_file(path, io::ConfigKind::kStudy);
  const io::JsonReader r(json, path);
  MonteCarloStudy s;
  s.spec = parse_study_spec(r, {"montecarlo"}, DesignKey::kRequired, kMinSamples);
  apply_design_overrides(overrides, s.spec);
  if (r.has("confidence")) {
    s.confidence = r.number("confidence");
    if (!(s.confidence > kMinConfidence && s.confidence < kMaxConfidence)) r.fail("confidence", "must lie in (0.5, 1)");
  }
  if (r.has("bootstrap")) {
    const io::IntegerRange resamples{kNoSdInterval, kMaxBootstrap,
                                     std::to_string(kNoSdInterval) + " (no sd interval), or from " +
                                         std::to_string(kMinBootstrap) + " to " + std::to_string(kMaxBootstrap)};
    s.bootstrap_resamples = r.integer("bootstrap", resamples);
    if (s.bootstrap_resamples != kNoSdInterval && s.bootstrap_resamples < kMinBootstrap)
      r.fail("bootstrap", io::whole_number_rule(resamples));
  }
  const bool sd_interval = s.bootstrap_resamples != kNoSdInterval;
  if (const std::string problem = sd_interval ? bootstrap_resolution_problem(s.confidence, "'confidence'",
                                                                             s.bootstrap_resamples, "'bootstrap'",
                                                                             kMaxBootstrap)
                                              : std::string();
      !problem.empty())
    r.fail("confidence", problem);
  if (s.spec.design.samples < kMinSamples && overrides.samples)
    throw std::invalid_argument("--samples " + std::to_string(*overrides.samples) + ": a Monte Carlo needs at least " +
                                std::to_string(kMinSamples) + " samples for its sd and bands");
  if (s.spec.design.samples < kMinSamples)
    r.fail("design", "a Monte Carlo needs at least " + std::to_string(kMinSamples) + " samples for its sd and bands, got " +
                         std::to_string(s.spec.design.samples));
  if (s.spec.rover && s.spec.rover->qoi_names().empty() && s.spec.rover->channel_names().empty())
    r.fail("qoi", "a Monte Carlo needs at least one of \"qoi\" and \"channels\"");
  r.finish();
  return s;
}

MonteCarloAnalysis::MonteCarloAnalysis(const RecordLayout& layout, int samples, double confidence,
                                       int bootstrap_resamples, std::uint64_t seed)
    : layout_(layout), confidence_(confidence), bootstrap_resamples_(bootstrap_resamples), seed_(seed) {
  result_.qoi.resize(static_cast<std::size_t>(layout.qoi_count));
  // Reserved once: a vector that doubles would hold its old and new arrays at once.
  const auto n = static_cast<std::size_t>(samples);
  for (auto& q : result_.qoi) q.reserve(n);
  result_.status.reserve(n);
  result_.messages.reserve(n);
  result_.wall_time_s.reserve(n);
  result_.rhs_evaluations.reserve(n);
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

MonteCarloResult MonteCarloAnalysis::finish() {
  MonteCarloResult out = std::move(result_);  // per-run vectors of 10^8 samples are not copied
  const std::vector<double> probabilities(std::begin(kTailProbabilities), std::end(kTailProbabilities));
  for (const auto& values : out.qoi)
    out.summaries.push_back(
        summarize_qoi(values, probabilities, confidence_, bootstrap_resamples_, seed_, &InterruptGuard::flag()));
  for (const StreamingBand& b : bands_) out.bands.push_back(b.result());
  return out;
}

MemoryEstimate montecarlo_memory(const MonteCarloStudy& study) {
  const StudySpec& spec = study.spec;
  const int N = spec.design.samples;
  const RecordLayout layout = spec.model->layout();
  // Per sample: the design twice while it is drawn (unit cube, then physical
  // units), the QoIs, the status, message, wall time and rhs evaluations,
  // and its index in the list of runs to do.
  const double per_sample = sizeof(double) * (2.0 * static_cast<double>(spec.inputs.size()) + layout.qoi_count) +
                            2 * sizeof(int) + sizeof(std::string) + sizeof(const char*) +
                            sizeof(double) * kPerSampleValues;
  const double bands = static_cast<double>(layout.channel_count) *
                       static_cast<double>(StreamingBand::memory_bytes_for(static_cast<std::size_t>(layout.time_samples),
                                                                           static_cast<std::size_t>(N)));
  return {"design, per-run results and band quantile heaps (N = " + std::to_string(N) + ")",
          static_cast<double>(N) * per_sample + bands};
}

MonteCarloResult run_montecarlo(const MonteCarloStudy& study, const StudyRuntime& runtime) {
  const StudySpec& spec = study.spec;
  const StudyModel& model = *spec.model;
  const RecordLayout layout = model.layout();
  const int N = spec.design.samples;
  DesignMatrix x = study_design(spec);
  const auto T = static_cast<std::size_t>(layout.time_samples);
  io::Hdf5Writer* h5 = runtime.h5;
  if (h5 != nullptr)
    for (const std::string& c : model.channel_names())
      h5->create_matrix("/curves/" + c, static_cast<std::size_t>(N), T, std::nan(""));
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
  stream_study_tasks(N, compute, consume, runtime.options);
  if (world_rank() != 0) return {};
  MonteCarloResult result = analysis.finish();
  for (std::size_t q = 0; q < result.summaries.size(); ++q)
    if (const std::string w = qoi_values_warning(spec, q, result.qoi[q]); !w.empty()) {
      std::string& note = result.summaries[q].note;
      note = "warning: " + w + (note.empty() ? "" : "\n    " + note);
    }
  result.study = study;
  result.inputs = std::move(x);
  return result;
}

StudyProgram<MonteCarloResult> montecarlo_program(MonteCarloStudy study) {
  const StudySpec& spec = study.spec;
  StudyProgram<MonteCarloResult> p;
  p.command = "montecarlo";
  p.name = spec.name;
  p.fingerprint = spec.fingerprint;
  p.inputs = spec.files;
  const bool grid = spec.design.type == DesignType::kGrid;
  p.banner = std::to_string(spec.design.samples) + " runs of " + runs_description(spec) + " over " +
             std::to_string(spec.inputs.size()) + " inputs (" + design_type_name(spec.design.type) +
             (grid ? "" : ", seed " + std::to_string(spec.design.seed)) + ") on " + std::to_string(world_size()) +
             " rank(s)";
  p.warnings = design_warnings(spec);
  if (grid)
    p.warnings.push_back("design: a grid is no random sample of the inputs' distributions; the intervals of the "
                         "mean, the sd and the quantiles assume one, and hold for the grid's points only");
  p.memory = montecarlo_memory(study);
  p.run = [study](const StudyRuntime& runtime) { return run_montecarlo(study, runtime); };
  p.provenance = [spec = study.spec](io::Hdf5Writer& h5) { write_study_provenance(h5, spec, spec.fingerprint); };
  p.write = write_montecarlo;
  p.counts = [](const MonteCarloResult& r) { return count_runs(r.status, r.messages); };
  p.report = report_montecarlo;
  p.plot = plot_montecarlo;
  p.figures = [study](PlotSelection plots) { return montecarlo_figures(study, plots); };
  return p;
}

}  // namespace rover::study
