// See surrogate_study.hpp.
#include "study/studies/surrogate_study.hpp"
#include "study/runtime/elapsed_time.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>

#include "io/hdf5_file.hpp"
#include "io/json_reader.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/study_output.hpp"
#include "study/studies/surrogate_report.hpp"

namespace rover::study {
namespace {

using Clock = std::chrono::steady_clock;

std::vector<Eigen::Index> ok_rows(const TrainingRuns& runs) {
  std::vector<Eigen::Index> rows;
  for (std::size_t i = 0; i < runs.status.size(); ++i)
    if (runs.status[i] == run_status::kOk) rows.push_back(static_cast<Eigen::Index>(i));
  return rows;
}

// The successful runs of one QoI: inputs and values.
struct QoiRuns {
  DesignMatrix x;
  Eigen::VectorXd y;
};

// With finite_only, also without the runs whose value of this QoI is not finite.
QoiRuns successful_runs(const TrainingRuns& runs, Eigen::Index qoi, bool finite_only = false) {
  std::vector<Eigen::Index> rows = ok_rows(runs);
  if (finite_only)
    rows.erase(std::remove_if(rows.begin(), rows.end(), [&](Eigen::Index i) { return !std::isfinite(runs.y(i, qoi)); }),
               rows.end());
  QoiRuns out{DesignMatrix(static_cast<Eigen::Index>(rows.size()), runs.x.cols()),
              Eigen::VectorXd(static_cast<Eigen::Index>(rows.size()))};
  for (std::size_t k = 0; k < rows.size(); ++k) {
    out.x.row(static_cast<Eigen::Index>(k)) = runs.x.row(rows[k]);
    out.y(static_cast<Eigen::Index>(k)) = runs.y(rows[k], qoi);
  }
  return out;
}

void fit_pce(const SurrogateStudy& study, const QoiRuns& runs, SurrogateQoiResult& r) {
  PceQoiResult p = pce_qoi_indices(r.name, runs.x, runs.y, study.distributions(), study.pce);
  r.fitted = p.fit_done;
  r.undefined_reason = p.undefined_reason;
  if (!r.fitted) return;
  r.model = polynomial_chaos_surrogate(std::move(p.expansion));
  r.indices_defined = p.indices.defined;
  r.indices = std::move(p.indices);
  r.has_intervals = p.has_intervals;
  r.intervals = std::move(p.intervals);
}

void fit_gp(const SurrogateStudy& study, const QoiRuns& runs, SurrogateQoiResult& r) {
  try {
    r.model = fit_gaussian_process_surrogate(runs.x, runs.y, study.distributions(), interruptible(study.gp), r.name);
    r.fitted = true;
  } catch (const std::invalid_argument& e) {
    r.undefined_reason = e.what();
  }
}

SurrogateQoiResult fit_qoi(const SurrogateStudy& study, const TrainingRuns& training, const TrainingRuns& held_out,
                           Eigen::Index q) {
  SurrogateQoiResult r;
  r.name = study.qoi_names()[static_cast<std::size_t>(q)];
  const QoiRuns runs = successful_runs(training, q);
  r.runs_used = static_cast<int>(runs.y.size());
  if (study.kind == SurrogateKind::kPolynomialChaos) fit_pce(study, runs, r);
  else fit_gp(study, runs, r);
  if (!r.fitted) return r;
  r.actual = runs.y;
  r.loo_predicted = leave_one_out_predictions(r.model, runs.x, runs.y);
  const QoiRuns test = successful_runs(held_out, q, /*finite_only=*/true);
  if (test.y.size() == 0) return r;
  validate_surrogate(test.x, test.y, study.q2_threshold(), &r.model);
  r.held_out_actual = test.y;
  r.held_out_predicted = predict_surrogate(r.model, test.x).mean;
  return r;
}

// Too few successful runs: a result file's is an input problem; the
// study's own runs are refused after they ran (the driver says that nothing
// was written and where the runs are kept), with the first failure's reason.
void check_run_count(const SurrogateStudy& study, const TrainingRuns& training) {
  const int ok = training.runs() - training.failed_runs(), needed = min_training_runs(study);
  if (ok >= needed) return;
  const std::string problem = training.source + ": " + std::to_string(ok) + " successful training runs (" +
                              std::to_string(training.failed_runs()) + " failed); a " +
                              surrogate_kind_name(study.kind) + " of " + std::to_string(study.spec.inputs.size()) +
                              " inputs needs at least " + std::to_string(needed);
  if (!study.training_file.empty()) throw io::ConfigError(problem);
  const RunCounts counts = count_runs(training.status, training.messages);
  throw RunsRefused(problem + (counts.failed > 0 ? " (first failure: " + counts.first_failure + ")" : ""),
                    "a --resume of this study would refuse them again; remove the cause of the failures and "
                    "start afresh with --restart (which discards them), or ask for more runs (--samples, "
                    "with --restart)");
}

// The successful training runs cover the support of every uniform or
// log-uniform input (support_coverage_problem): a result file's runs are an
// input problem, the study's own runs (their failures gathered at an end)
// are refused after they ran, as too few successful runs are.
void check_coverage(const SurrogateStudy& study, const TrainingRuns& training) {
  const QoiRuns ok = successful_runs(training, 0);
  std::string problems;
  for (std::size_t j = 0; j < study.spec.inputs.size(); ++j) {
    const UncertainInput& in = study.spec.inputs[j];
    const std::string p = support_coverage_problem(in.label, in.distribution, ok.x.col(static_cast<Eigen::Index>(j)));
    if (!p.empty()) problems += (problems.empty() ? "" : "; ") + p;
  }
  if (problems.empty()) return;
  if (!study.training_file.empty())
    throw io::ConfigError(study.spec.path + ": field 'training.file': " + training.source + ": " + problems);
  throw RunsRefused(training.source + " runs: " + problems,
                    "a --resume of this study would refuse them again; ask for more runs (--samples, with "
                    "--restart, which discards them) or narrow the inputs the runs leave uncovered");
}

SurrogateSet surrogate_set(const SurrogateStudy& study, const TrainingRuns& training,
                           const std::vector<SurrogateQoiResult>& qoi) {
  SurrogateSet set;
  set.kind = study.kind;
  set.q2_threshold = study.q2_threshold();
  const QoiRuns ok = successful_runs(training, 0);
  for (std::size_t j = 0; j < study.spec.inputs.size(); ++j) {
    const UncertainInput& in = study.spec.inputs[j];
    set.inputs.push_back(surrogate_input(in.name, in.label, in.distribution, ok.x.col(static_cast<Eigen::Index>(j))));
  }
  for (const SurrogateQoiResult& q : qoi)
    if (q.fitted) set.models.push_back(q.model);
  return set;
}

// The curves of the successful training runs, per channel.
std::vector<PceChannelResult> fit_channels(const SurrogateStudy& study, const TrainingRuns& training) {
  std::vector<PceChannelResult> out;
  const std::vector<Eigen::Index> rows = ok_rows(training);
  DesignMatrix x(static_cast<Eigen::Index>(rows.size()), training.x.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) x.row(static_cast<Eigen::Index>(k)) = training.x.row(rows[k]);
  const std::vector<std::string>& names = study.spec.model->channel_names();
  for (std::size_t c = 0; c < training.curves.size(); ++c) {
    const Eigen::MatrixXd& all = training.curves[c];
    Eigen::MatrixXd y(static_cast<Eigen::Index>(rows.size()), all.cols());
    for (std::size_t k = 0; k < rows.size(); ++k) y.row(static_cast<Eigen::Index>(k)) = all.row(rows[k]);
    out.push_back(pce_channel_indices(names[c], x, y, study.distributions(), study.pce));
  }
  return out;
}

std::vector<std::string> study_warnings(const SurrogateStudy& study, const SurrogateStudyResult& r) {
  std::vector<std::string> w;
  for (Eigen::Index q = 0; q < r.training.y.cols(); ++q) {
    const Eigen::VectorXd column = r.training.y.col(q);
    const std::string values_warning = qoi_values_warning(study.spec, static_cast<std::size_t>(q),
                                                    std::vector<double>(column.data(), column.data() + column.size()));
    if (!values_warning.empty()) w.push_back(values_warning);
  }
  for (const PceChannelResult& c : r.channels) {
    if (!c.defined) w.push_back(c.name + ": indices along time undefined: " + c.undefined_reason);
    else if (!c.curves.warning.empty()) w.push_back(c.curves.warning);
  }
  if (const long long repeats = repeated_runs(r.training); repeats > 0)
    w.push_back(std::to_string(repeats) + " of " + std::to_string(r.training.runs()) + " training runs repeat " +
                "the inputs of another: leave-one-out Q2 leaves one copy out while the others stay in the fit, " +
                "so it overstates the accuracy; drop the repeats, or judge by held-out runs");
  if (const std::string mismatch = integrator_mismatch(study, r.training, r.held_out); !mismatch.empty())
    w.push_back(mismatch);
  if (!r.training.unchecked_provenance.empty()) w.push_back("training runs: " + r.training.unchecked_provenance);
  if (!r.held_out.unchecked_provenance.empty() && r.held_out.source != r.training.source)
    w.push_back("held-out runs: " + r.held_out.unchecked_provenance);
  for (const TrainingRuns* runs : {&r.training, &r.held_out})
    if (runs->failed_runs() > 0)
      w.push_back(std::to_string(runs->failed_runs()) + " of " + std::to_string(runs->runs()) +
                  (runs == &r.training ? " training" : " held-out") + " runs failed and were left out (" +
                  runs->source + ", see /samples/status)");
  for (const SurrogateQoiResult& q : r.qoi) {
    if (!q.fitted) w.push_back(q.name + ": no surrogate: " + q.undefined_reason);
    else if (!q.undefined_reason.empty()) w.push_back(q.name + ": indices undefined: " + q.undefined_reason);
    if (q.fitted && q.undefined_reason.empty() && !q.model.validation().warning.empty())
      w.push_back(q.model.validation().warning);
    if (const std::string distrust = q.fitted ? surrogate_not_to_trust(q.name, q.model.validation()) : "";
        !distrust.empty())
      w.push_back(distrust + " (exit status 2)");
    if (const std::string why = q.fitted ? held_out_q2_undefined_reason(q.model.validation()) : ""; !why.empty())
      w.push_back(q.name + ": held-out Q2 undefined: " + why);
    if (q.has_intervals)
      if (const std::string fixed = pce_fixed_by_selection_warning(q.name, q.intervals, input_labels(study.spec),
                                                                    q.model.validation().q2_loo,
                                                                    study.q2_threshold());
          !fixed.empty())
        w.push_back(fixed);
    if (q.indices_defined && study.pce.bootstrap > 0 && !q.has_intervals)
      w.push_back(q.name + ": " + std::to_string(q.intervals.resamples_used) + " of " +
                  std::to_string(study.pce.bootstrap) +
                  " bootstrap resamples could be refitted (too few distinct runs for the expansion); the indices "
                  "have no intervals: use more runs");
  }
  return w;
}

// The total indices of the "compare" file, matched by input name; a QoI or
// input it lacks is left empty (load_surrogate_study warned of it before any run).
void read_compared(const SurrogateStudy& study, SurrogateStudyResult& r) {
  if (study.compare_file.empty()) return;
  const io::Hdf5Reader h5(study.compare_file);
  const std::vector<std::string> names =
      h5.exists("/inputs/names") ? h5.read_strings("/inputs/names") : std::vector<std::string>{};
  for (const std::string& q : study.qoi_names()) {
    SurrogateStudyResult::ComparedIndices c;
    const std::string g = "/indices/" + q + "/";
    std::vector<std::size_t> columns;
    for (const UncertainInput& in : study.spec.inputs) {
      const auto it = std::find(names.begin(), names.end(), in.name);
      if (it != names.end()) columns.push_back(static_cast<std::size_t>(it - names.begin()));
    }
    if (!h5.exists(g + "ST") || columns.size() != study.spec.inputs.size()) {
      r.compared.push_back(c);
      continue;
    }
    const auto pick = [&](const std::string& name) {
      const std::vector<double> all = h5.exists(g + name) ? h5.read_doubles(g + name) : h5.read_doubles(g + "ST");
      Eigen::VectorXd v(static_cast<Eigen::Index>(columns.size()));
      for (std::size_t j = 0; j < columns.size(); ++j) v(static_cast<Eigen::Index>(j)) = all.at(columns[j]);
      return v;
    };
    c.ST = pick("ST");
    c.ST_lower = pick("ST_lower");
    c.ST_upper = pick("ST_upper");
    r.compared.push_back(c);
  }
}

// The runs of the file named by '<field>.file', errors naming that field.
TrainingRuns read_named_runs(const SurrogateStudy& study, const std::string& file, const std::string& field) {
  try {
    return read_result_runs(file, study, field == "held_out" ? "held-out" : field);
  } catch (const io::ConfigError& e) {
    throw io::ConfigError(study.spec.path + ": field '" + field + ".file': " + e.what());
  }
}

// Every run of the study's design failed: nothing to fit. The result holds
// the failed runs and no model, so that the driver treats it as every
// study whose every run failed (an earlier result kept, exit status 2).
bool every_design_run_failed(const SurrogateStudy& study, const TrainingRuns& training, const TrainingRuns& held_out) {
  return study.training_file.empty() && training.runs() + held_out.runs() > 0 &&
         training.failed_runs() == training.runs() && held_out.failed_runs() == held_out.runs();
}

SurrogateStudyResult failed_runs_result(const SurrogateStudy& study, const TrainingRuns& training,
                                        const TrainingRuns& held_out) {
  SurrogateStudyResult r;
  r.training = training;
  r.held_out = held_out;
  const RunCounts counts = count_runs(training.status, training.messages);
  for (const std::string& name : study.qoi_names()) {
    SurrogateQoiResult q;
    q.name = name;
    q.undefined_reason = "every run failed (first: " + counts.first_failure + ")";
    r.qoi.push_back(std::move(q));
  }
  r.set.kind = study.kind;
  r.set.q2_threshold = study.q2_threshold();
  for (const UncertainInput& in : study.spec.inputs)
    r.set.inputs.push_back({in.name, in.label, in.distribution, in.distribution.support_lower(),
                            in.distribution.support_upper(), ""});
  return r;
}

}  // namespace

SurrogateStudyResult fit_surrogate_study(const SurrogateStudy& study, const TrainingRuns& training,
                                         const TrainingRuns& held_out) {
  if (every_design_run_failed(study, training, held_out)) return failed_runs_result(study, training, held_out);
  check_run_count(study, training);
  check_coverage(study, training);
  SurrogateStudyResult r;
  r.training = training;
  r.held_out = held_out;
  const auto start = Clock::now();
  for (Eigen::Index q = 0; q < training.y.cols(); ++q) r.qoi.push_back(fit_qoi(study, training, held_out, q));
  if (study.kind == SurrogateKind::kPolynomialChaos) r.channels = fit_channels(study, training);
  r.fit_wall_time_s = seconds_since(start);
  r.set = surrogate_set(study, training, r.qoi);
  r.warnings = study_warnings(study, r);
  return r;
}

SurrogateStudyResult run_surrogate_study(const SurrogateStudy& study, const StudyRuntime& runtime) {
  const std::string& out = runtime.options.results_path;
  const bool root = world_rank() == 0;
  const auto start = Clock::now();
  TrainingRuns runs;
  if (study.training_file.empty()) runs = run_design_runs(study, runtime.options);
  else if (root) runs = read_named_runs(study, study.training_file, "training");
  if (!root) return {};
  const double runs_s = seconds_since(start);
  TrainingRuns held_out;
  if (!study.held_out_file.empty()) {
    held_out = read_named_runs(study, study.held_out_file, "held_out");
  } else {
    const int count = static_cast<int>(std::lround(study.held_out_fraction * runs.runs()));
    if (study.held_out_fraction > 0.0)  // of a training file: its run count is known now
      if (const std::string p = held_out_count_problem(study.held_out_fraction, runs.runs()); !p.empty())
        throw io::ConfigError(study.spec.path + ": field 'held_out.fraction': " + runs.source + ": " + p);
    held_out = runs.slice(runs.runs() - count, count);
    runs = runs.slice(0, runs.runs() - count);
  }
  if (const std::string shared = shared_runs(runs, held_out); !shared.empty())
    throw io::ConfigError(study.spec.path + ": field 'held_out.file': " + shared);
  SurrogateStudyResult result = fit_surrogate_study(study, runs, held_out);
  read_compared(study, result);
  result.results_path = out;
  result.runs_wall_time_s = runs_s;
  return result;
}

StudyProgram<SurrogateStudyResult> surrogate_program(SurrogateStudy study) {
  StudyProgram<SurrogateStudyResult> p;
  p.command = "surrogate";
  p.name = study.spec.name;
  p.fingerprint = study.spec.fingerprint;
  p.banner = std::string(surrogate_kind_name(study.kind)) + " of " + std::to_string(study.qoi_names().size()) +
             " QoI(s) over " + std::to_string(study.spec.inputs.size()) + " inputs, trained on " +
             (study.training_file.empty()
                  ? std::to_string(study.spec.design.samples) + " runs of " + runs_description(study.spec) + " (" +
                        design_type_name(study.spec.design.type) + ") on " + std::to_string(world_size()) +
                        " rank(s)"
                  : study.training_file);
  p.warnings = design_warnings(study.spec);
  const auto s = std::make_shared<const SurrogateStudy>(std::move(study));
  p.run = [s](const StudyRuntime& runtime) { return run_surrogate_study(*s, runtime); };
  p.write = [s](const SurrogateStudyResult& r, io::Hdf5Writer& h5) { write_surrogate_study(h5, *s, r); };
  p.counts = [](const SurrogateStudyResult& r) {
    std::vector<int> status = r.training.status;
    status.insert(status.end(), r.held_out.status.begin(), r.held_out.status.end());
    std::vector<std::string> messages = r.training.messages;
    messages.insert(messages.end(), r.held_out.messages.begin(), r.held_out.messages.end());
    return count_runs(status, messages);
  };
  p.report = [s](const SurrogateStudyResult& r, std::ostream& out) { report_surrogate_study(out, *s, r); };
  // A QoI without a surrogate, or with one not to be trusted (its reason is
  // among the warnings), is a result not to use as it is.
  p.verdict = [](const SurrogateStudyResult& r) {
    return std::all_of(r.qoi.begin(), r.qoi.end(),
                       [](const SurrogateQoiResult& q) {
                         return q.fitted && surrogate_not_to_trust(q.name, q.model.validation()).empty();
                       })
               ? 0
               : kSomeQoiUnfittedStatus;
  };
  p.plot = [s](const SurrogateStudyResult& r, const std::string&, PlotSelection) {
    plot_surrogate_study(*s, r, std::cerr);
  };
  p.figures = [s](PlotSelection) { return surrogate_figures(*s); };
  return p;
}

}  // namespace rover::study
