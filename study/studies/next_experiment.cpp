// See next_experiment.hpp.
#include "study/studies/next_experiment.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <iostream>
#include <ostream>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>

#include "core/number_text.hpp"
#include "io/config_kind.hpp"
#include "io/csv.hpp"
#include "io/json_reader.hpp"
#include "io/result_label.hpp"
#include "io/scenario_config.hpp"
#include "study/model/parameter_space.hpp"
#include "study/runtime/rank0_broadcast.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/calibration_fit.hpp"
#include "study/studies/calibration_program.hpp"
#include "study/studies/measurement_noise_scale.hpp"
#include "study/studies/study_output.hpp"

namespace rover::study {
namespace {

constexpr double kZ975 = 1.959963984540054;  // the standard normal's 97.5 % quantile
constexpr double kMaxRateHz = 1e5;

std::string number(double v, int digits = 4) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

// The candidate's scenario with its "set" values applied, built: its
// duration. A scenario the model refuses only with those values is blamed on
// "set" in the candidates file, with the values, not on the scenario file,
// which holds others.
double candidate_duration_s(const io::JsonReader& c, const NextExperimentCandidate& candidate) {
  if (!c.has("set")) return io::build_scenario(candidate.sources).scenario.duration_s;
  try {
    return io::build_scenario(candidate.sources).scenario.duration_s;
  } catch (const std::exception& e) {
    c.fail("set", "with these values, the model refuses the scenario " + candidate.scenario_path + ": " + e.what());
  }
}

// A fitted parameter in a candidate's "set" would be ignored: the candidate
// is simulated at the estimate, whatever it sets.
void refuse_setting_a_fitted_parameter(const io::JsonReader& set, const std::string& name,
                                       const std::string& canonical, const CalibrationStudy& study) {
  for (const FitParameter& f : study.fit) {
    if (!f.canonical.empty() && f.canonical == canonical)
      set.fail(name, "'" + f.name + "' is fitted by the study: a candidate is simulated at its estimate, so a value "
                     "set here would be ignored; remove it, or set only parameters the study does not fit");
    if (!f.canonical.empty() && parameters_overlap(f.canonical, canonical))
      set.fail(name, "overlaps '" + f.name + "', which the study fits: " + overlap_reason(f.canonical, canonical) +
                         "; set only parameters the study does not fit");
  }
}

// Two keys of a candidate's "set" that set a common number: the candidate
// would depend on the order of its keys.
void refuse_overlapping_settings(const io::JsonReader& set, const std::string& name, const std::string& canonical,
                                 const std::vector<std::pair<std::string, std::string>>& earlier) {
  for (const auto& [earlier_name, earlier_canonical] : earlier) {
    if (earlier_canonical == canonical)
      set.fail(name, "is the same parameter as '" + earlier_name + "'; give it once");
    if (parameters_overlap(earlier_canonical, canonical))
      set.fail(name, "overlaps '" + earlier_name + "': " + overlap_reason(earlier_canonical, canonical));
  }
}

NextExperimentCandidate read_candidate(const io::JsonReader& c, std::size_t index,
                                       const CalibrationStudy& study) {
  NextExperimentCandidate out;
  out.name = c.string_or("name", "candidate " + std::to_string(index));
  if (const std::string problem = io::display_name_problem(out.name); !problem.empty()) c.fail("name", problem);
  out.scenario_path = io::named_input_file(c, "scenario", "a JSON file");
  out.channel = c.string_or("channel", "B_l_z");
  try {
    (void)calibration_channel(out.channel);
  } catch (const std::invalid_argument& e) {
    c.fail("channel", e.what());
  }
  out.rate_hz = c.positive("rate_hz");
  if (out.rate_hz > kMaxRateHz) c.fail("rate_hz", "must be at most 1e5 Hz, got " + number(out.rate_hz, 6));
  out.noise_sd_m = c.number("noise_sd");
  if (!noise_sd_resolved(out.noise_sd_m)) c.fail("noise_sd", noise_scale_problem(out.noise_sd_m));
  try {
    out.sources = io::read_scenario_sources(out.scenario_path);
  } catch (const std::exception& e) {
    c.fail("scenario", e.what());
  }
  if (c.has("set")) {
    const io::JsonReader set = c.child("set");
    const io::Json rover = out.sources.rover, scenario = out.sources.scenario;
    const ParameterSpace space(rover, scenario);
    std::vector<std::pair<std::string, std::string>> earlier;  // (key, canonical name) of the keys before
    for (const auto& [name, value] : c.raw("set").items()) {
      std::string canonical;
      try {
        canonical = space.canonical(name);
      } catch (const std::invalid_argument& e) {
        set.fail(name, e.what());
      }
      refuse_setting_a_fitted_parameter(set, name, canonical, study);
      refuse_overlapping_settings(set, name, canonical, earlier);
      earlier.emplace_back(name, canonical);
      space.apply(canonical, set.number(name), out.sources.rover, out.sources.scenario);
    }
    set.finish();
  }
  // The scenario's own checks, with "set" applied; then the data clock: a
  // curve of fewer samples than rover compare and calibrate accept has no
  // place in a ranking of curves.
  const double duration_s = candidate_duration_s(c, out);
  if (const double samples = io::recorded_sample_count(duration_s, out.rate_hz);
      samples < static_cast<double>(io::kMeasuredCurveMinRows))
    c.fail("rate_hz", number(out.rate_hz, 6) + " Hz over the " + number(duration_s, 6) + " s of " +
                          out.scenario_path + " gives " + number_text(samples) + " sample(s); a curve needs at least " +
                          std::to_string(io::kMeasuredCurveMinRows) + " (as rover compare and calibrate): give at "
                          "least " + number((io::kMeasuredCurveMinRows - 1) / duration_s, 6) + " Hz");
  return out;
}

// The candidate as a one-curve study: its scenario and channel, a time grid
// at its rate over its duration, and no data (residuals are the model).
CalibrationStudy candidate_study(const CalibrationStudy& study, const NextExperimentCandidate& c) {
  CalibrationStudy s = study;
  CalibrationDataset d;
  d.path = c.name;
  d.scenario_path = c.scenario_path;
  d.channel = c.channel;
  d.sources = c.sources;
  const double duration_s = io::build_scenario(c.sources).scenario.duration_s;
  for (double t = 0.0; t <= duration_s + 1e-12; t = static_cast<double>(d.t.size()) / c.rate_hz) d.t.push_back(t);
  d.z.assign(d.t.size(), 0.0);
  s.datasets = {d};
  return s.with_integrator(study.integrator);
}

// Expected 95 % half-widths of the fitted parameters (the first p of the
// information matrix's unknowns).
Eigen::VectorXd half_widths(const Eigen::MatrixXd& information, std::size_t p) {
  const Eigen::MatrixXd covariance = information.completeOrthogonalDecomposition().pseudoInverse();
  Eigen::VectorXd out(static_cast<Eigen::Index>(p));
  for (Eigen::Index i = 0; i < out.size(); ++i) out[i] = kZ975 * std::sqrt(std::max(covariance(i, i), 0.0));
  return out;
}

}  // namespace

std::vector<NextExperimentCandidate> load_next_experiment_candidates(const std::string& path,
                                                                     const CalibrationStudy& study) {
  const io::Json json = io::read_config_file(path, io::ConfigKind::kCandidates);
  const io::JsonReader r(json, path);
  (void)r.string_or("description", "");
  if (study.offset_fitted())
    r.fail("candidates", "ranking experiments needs each curve's time offset profiled: remove time_offset from the "
                         "study's \"fit\"");
  const io::Json& list = r.raw("candidates");
  if (!list.is_array() || list.empty()) r.fail("candidates", "expected a non-empty list of candidate experiments");
  std::vector<NextExperimentCandidate> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_object()) r.fail("candidates", "entry " + std::to_string(i) + " is not an object");
    const io::JsonReader c(list[i], path, r.field("candidates") + "[" + std::to_string(i) + "]");
    out.push_back(read_candidate(c, i, study));
    for (std::size_t j = 0; j < i; ++j)  // the ranking names each candidate: two of one name could not be told apart
      if (out[j].name == out[i].name)
        c.fail("name", "candidates[" + std::to_string(j) + "] has this name too: give each candidate its own name");
    c.finish();
  }
  r.finish();
  return out;
}

NextExperimentRanking rank_next_experiments(const CalibrationStudy& study,
                                            const std::vector<NextExperimentCandidate>& candidates,
                                            const StudyRunOptions& control) {
  const CalibrationEstimate estimate = estimate_calibration(study, control, control.results_path);
  NextExperimentRanking out;
  out.fit_trusted = estimate.trusted;
  out.not_valid_because = estimate.not_valid_because;
  if (!estimate.valid) {
    out.message = "no ranking: " + estimate.why_not;
    return out;
  }
  const std::size_t p = study.fit.size();
  std::vector<Eigen::MatrixXd> candidate_jacobians;
  for (const NextExperimentCandidate& c : candidates) {
    const CalibrationJacobian j = calibration_jacobian(candidate_study(estimate.study, c), estimate.values, {0.0},
                                                       control.progress_interval_s);
    if (!j.ok) {
      out.message = "no ranking: the candidate '" + c.name + "' could not be simulated at the estimate (" +
                    j.message + ")";
      return out;
    }
    candidate_jacobians.push_back(j.jacobian / c.noise_sd_m);
  }
  if (estimate.weighted_jacobian.size() == 0) return out;  // the ranks without the information
  const Eigen::MatrixXd current = estimate.weighted_jacobian.transpose() * estimate.weighted_jacobian /
                                  (estimate.noise_sd * estimate.noise_sd);
  const Eigen::Index q = current.rows();
  out.parameters.assign(estimate.names.begin(), estimate.names.begin() + static_cast<std::ptrdiff_t>(p));
  out.current_half_width = half_widths(current, p);
  out.estimate = estimate.values;
  std::vector<Eigen::VectorXd> widths;
  std::vector<double> scores;
  for (const Eigen::MatrixXd& j : candidate_jacobians) {
    Eigen::MatrixXd information = Eigen::MatrixXd::Zero(q + 1, q + 1);
    information.topLeftCorner(q, q) = current;
    Eigen::MatrixXd columns(j.rows(), static_cast<Eigen::Index>(p) + 1);  // the fitted parameters, its offset
    columns << j.leftCols(static_cast<Eigen::Index>(p)), j.col(static_cast<Eigen::Index>(p));
    std::vector<Eigen::Index> unknowns(p);
    std::iota(unknowns.begin(), unknowns.end(), 0);
    unknowns.push_back(q);
    const Eigen::MatrixXd added = columns.transpose() * columns;
    for (std::size_t a = 0; a <= p; ++a)
      for (std::size_t b = 0; b <= p; ++b) information(unknowns[a], unknowns[b]) += added(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
    widths.push_back(half_widths(information, p));
    scores.push_back(std::exp((widths.back().array() / out.current_half_width.array()).log().mean()));
  }
  std::vector<std::size_t> order(candidates.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return scores[a] < scores[b]; });
  out.expected_half_width.resize(static_cast<Eigen::Index>(order.size()), static_cast<Eigen::Index>(p));
  out.score.resize(static_cast<Eigen::Index>(order.size()));
  for (std::size_t r = 0; r < order.size(); ++r) {
    out.candidates.push_back(candidates[order[r]].name);
    out.expected_half_width.row(static_cast<Eigen::Index>(r)) = widths[order[r]].transpose();
    out.score[static_cast<Eigen::Index>(r)] = scores[order[r]];
  }
  out.ok = true;
  return out;
}

StudyProgram<NextExperimentRanking> next_experiment_program(CalibrationStudy study, const std::string& candidates_path) {
  const std::vector<NextExperimentCandidate> candidates = load_next_experiment_candidates(candidates_path, study);
  StudyProgram<NextExperimentRanking> p;
  p.command = "calibrate";
  p.name = study.identity.name + "_next_experiment";
  p.fingerprint = extend_fingerprint(study.fingerprint, file_text(candidates_path));
  p.banner = "ranking " + std::to_string(candidates.size()) + " candidate experiments of " + candidates_path +
             " after fitting " + study.data_path + " on " + std::to_string(world_size()) + " rank(s)";
  p.run = [study, candidates](const StudyRuntime& runtime) {
    return rank_next_experiments(study, candidates, runtime.options);
  };
  p.provenance = [study, candidates_path](io::Hdf5Writer& h5) {
    write_calibration_provenance(h5, study);
    h5.attribute("/", "candidates_file", candidates_path);
  };
  p.write = write_next_experiment;
  p.counts = [](const NextExperimentRanking&) { return RunCounts{}; };
  p.report = report_next_experiment;
  p.verdict = [](const NextExperimentRanking& r) { return r.ok && r.fit_trusted ? 0 : kUntrustedStatus; };
  p.holds_nothing = [](const NextExperimentRanking& r) { return r.ok ? std::string() : r.message; };
  return p;
}

void write_next_experiment(const NextExperimentRanking& ranking, io::Hdf5Writer& h5) {
  h5.create_group("/next_experiment");
  h5.attribute("/next_experiment", "ranked", static_cast<long long>(ranking.ok ? 1 : 0));
  if (!ranking.ok) {
    h5.attribute("/next_experiment", "not_ranked_because", ranking.message);
    return;
  }
  h5.attribute("/next_experiment", "ranking_valid", static_cast<long long>(ranking.fit_trusted ? 1 : 0));
  const std::string flaw = "the fit it is computed at is NOT VALID: " + ranking.not_valid_because;
  h5.attribute("/next_experiment", "not_valid_because", ranking.fit_trusted ? std::string() : flaw);
  h5.write("/next_experiment/candidates", ranking.candidates);
  h5.write("/next_experiment/parameters", ranking.parameters);
  h5.write("/next_experiment/estimate", ranking.estimate);
  h5.write("/next_experiment/current_half_width_95", std::vector<double>(ranking.current_half_width.begin(),
                                                                         ranking.current_half_width.end()));
  h5.write("/next_experiment/expected_half_width_95", ranking.expected_half_width);
  h5.write("/next_experiment/score", std::vector<double>(ranking.score.begin(), ranking.score.end()));
  h5.attribute("/next_experiment", "meaning",
               std::string("candidates in rank order; expected 95 % half-widths of the fitted parameters with the "
                           "candidate's curve added; score: geometric mean of expected / current half-width"));
}

void report_next_experiment(const NextExperimentRanking& ranking, std::ostream& out) {
  if (!ranking.ok) {
    out << "calibrate: " << ranking.message << "\n";
    return;
  }
  if (!ranking.fit_trusted)
    out << "calibrate: WARNING: the ranking below is NOT VALID: the fit it is computed at is NOT VALID: "
        << ranking.not_valid_because
        << ". It is written flagged (/next_experiment ranking_valid = 0) and the exit status is 2.\n";
  out << "calibrate: candidate experiments ranked by the expected 95 % half-width of each parameter (now:";
  for (std::size_t k = 0; k < ranking.parameters.size(); ++k)
    out << " " << ranking.parameters[k] << " +-" << number(ranking.current_half_width[static_cast<Eigen::Index>(k)], 3);
  out << ")\n  rank  score  ";
  for (const std::string& name : ranking.parameters) out << name << " +-  ";
  out << "candidate\n";
  for (std::size_t r = 0; r < ranking.candidates.size(); ++r) {
    const auto i = static_cast<Eigen::Index>(r);
    char head[32];
    std::snprintf(head, sizeof head, "  %4zu  %5.3f  ", r + 1, ranking.score[i]);
    out << head;
    for (Eigen::Index k = 0; k < ranking.expected_half_width.cols(); ++k)
      out << number(ranking.expected_half_width(i, k), 3) << "  ";
    out << ranking.candidates[r] << "\n";
  }
}

}  // namespace rover::study
