// See sensitivity.hpp: the study's configuration, design, runs and analysis.
#include "study/studies/sensitivity.hpp"
#include "study/estimators/bootstrap_resolution.hpp"
#include "study/runtime/elapsed_time.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <numeric>
#include <sstream>

#include "core/number_text.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/report_format.hpp"
#include "study/studies/study_output.hpp"
#include "io/config_kind.hpp"

namespace rover::study {
namespace {

// Rank 0 holds every run's record; the vectors holding them take about this
// much more than the values themselves.
constexpr double kRecordOverhead = 1.2;
// A bootstrap of indices: 0 (no intervals), or this many resamples.
constexpr int kMinBootstrap = 100, kMaxBootstrap = 100000;
// Morris trajectories, and the levels of its grid (even: each step spans half of them).
constexpr int kMinStudyTrajectories = 2, kMaxStudyTrajectories = 100000;
constexpr int kMinMorrisLevels = 2, kMaxMorrisLevels = 1000, kDefaultMorrisLevels = 4;

int varied_count(const StudySpec& spec) { return static_cast<int>(spec.inputs.size()); }

// Where in input space runs failed: per input, the range of the failed runs'
// values against the whole design's.
std::string failure_report(const StudySpec& spec, const DesignMatrix& x, const std::vector<int>& status) {
  std::vector<Eigen::Index> failed;
  for (std::size_t i = 0; i < status.size(); ++i)
    if (status[i] != run_status::kOk) failed.push_back(static_cast<Eigen::Index>(i));
  if (failed.empty()) return "";
  std::ostringstream os;
  os << failed.size() << " of " << status.size() << " runs failed; their inputs span:";
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    double lo = INFINITY, hi = -INFINITY;
    for (Eigen::Index i : failed) {
      lo = std::min(lo, x(i, j));
      hi = std::max(hi, x(i, j));
    }
    os << "\n    " << spec.inputs[static_cast<std::size_t>(j)].label << " in [" << lo << ", " << hi << "] (design ["
       << x.col(j).minCoeff() << ", " << x.col(j).maxCoeff() << "])";
  }
  return os.str();
}

// How many base samples would make the widest interval about `target` wide
// (intervals shrink like N^-1/2).
long suggested_samples(int n, double widest, double target) {
  return static_cast<long>(std::ceil(n * std::pow(widest / target, 2)));
}

// "; the indices themselves are sampling noise at this size: x3 S1 -0.395
// below 0, x2 S1 0.521 above its ST 0.461", for indices no variance share can
// have (outside [0, 1], or a first-order above its total); empty when none.
std::string impossible_indices_note(const SobolIndices& s, const std::vector<std::string>& labels) {
  std::string found;
  const auto add = [&](Eigen::Index i, const std::string& what) {
    found += (found.empty() ? "" : ", ") + labels[static_cast<std::size_t>(i)] + " " + what;
  };
  for (Eigen::Index i = 0; i < s.S1.size(); ++i) {
    for (const auto& [index, value] : {std::pair<const char*, double>{"S1", s.S1[i]}, {"ST", s.ST[i]}}) {
      if (value < 0.0) add(i, std::string(index) + " " + fixed_text(value) + " below 0");
      if (value > 1.0) add(i, std::string(index) + " " + fixed_text(value) + " above 1");
    }
    if (s.S1[i] > s.ST[i]) add(i, "S1 " + fixed_text(s.S1[i]) + " above its ST " + fixed_text(s.ST[i]));
  }
  return found.empty() ? "" : "; the indices themselves are sampling noise at this size: " + found;
}

std::vector<std::string> sobol_warnings(const std::string& qoi, const SobolIndices& s,
                                        const std::vector<std::string>& labels, int n) {
  std::vector<std::string> w;
  double widest = 0.0;
  for (Eigen::Index i = 0; i < s.S1.size(); ++i) {
    const double width = std::max(s.S1_upper[i] - s.S1_lower[i], s.ST_upper[i] - s.ST_lower[i]);
    widest = std::max(widest, width);
    const double index = std::max(std::abs(s.S1[i]), std::abs(s.ST[i]));
    if (width > index && index > 0.01)
      w.push_back(qoi + ": the interval of " + labels[static_cast<std::size_t>(i)] + " (width " + fixed_text(width) +
                  ") is wider than its index (" + fixed_text(index) + ")");
  }
  const double s1_sum = s.S1.sum();
  const double s1_sum_upper_slack = (s.S1_upper - s.S1).sum();
  if (s1_sum - 1.0 > s1_sum_upper_slack)
    w.push_back(qoi + ": the first-order indices sum to " + fixed_text(s1_sum) + ", above 1 beyond their intervals");
  if (!w.empty() && widest > 0.05)
    w.push_back(qoi + ": for intervals about 0.05 wide, use about N = " + std::to_string(suggested_samples(n, widest, 0.05)) +
                " base samples (now " + std::to_string(n) + ")");
  return w;
}

// A spread of the values within this many units of rounding of their
// magnitude is rounding, not a response (the bound the Sobol' estimator
// puts on a zero variance, study/estimators/sobol_indices.cpp).
constexpr double kRoundingUnits = 16.0;

// Why a QoI's indices are undefined: it does not vary over the runs that
// succeeded, or only at rounding level ("" when it does), for Sobol' and
// Morris alike.
std::string constant_qoi_reason(const std::vector<double>& values) {
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (!(hi >= lo)) return "no run gave a finite value";
  const double rounding = kRoundingUnits * std::numeric_limits<double>::epsilon() * std::max(std::abs(lo), std::abs(hi));
  if (hi - lo > rounding) return "";
  std::ostringstream os;
  os << "constant (" << lo << ") over every run that succeeded";
  if (hi > lo) os << " up to rounding (spread " << hi - lo << ")";
  os << ": its variance is zero";
  return os.str();
}

// The Sobol' indices or Morris effects of one QoI, appended to `out`; an
// empty entry, its reason in out.undefined, when they are undefined.
void estimate_qoi_indices(const SensitivityStudy& study, const MorrisDesign& morris, const std::string& name,
                          const std::vector<std::string>& labels, const std::vector<double>& values,
                          SensitivityResult& out) {
  const Eigen::Map<const Eigen::VectorXd> y(values.data(), static_cast<Eigen::Index>(values.size()));
  const bool sobol = study.method == SensitivityMethod::kSobol;
  if (sobol) out.sobol.emplace_back();
  else out.morris.emplace_back();
  std::string reason = constant_qoi_reason(values);
  if (reason.empty()) {
    try {
      if (sobol) {
        SobolOptions options = study.sobol;
        options.stop = &InterruptGuard::flag();  // a signal ends the bootstrap at once
        out.sobol.back() = estimate_sobol_indices(study.layout, y, options);
      } else {
        MorrisOptions options = study.morris;
        options.stop = &InterruptGuard::flag();
        out.morris.back() = morris_effects(morris, y, options);
      }
    } catch (const std::invalid_argument& e) {
      reason = e.what();
    }
  }
  if (sobol && reason.empty() && !out.sobol.back().S1.allFinite())
    reason = "its variance is zero at rounding level";
  if (!reason.empty()) {
    if (sobol) out.sobol.back() = SobolIndices{};
    else out.morris.back() = MorrisResult{};
    out.undefined.push_back({name, reason});
    out.warnings.push_back(name + ": indices undefined: " + reason);
    return;
  }
  if (sobol && study.sobol.bootstrap_resamples > 0 && !out.sobol.back().has_intervals)
    out.warnings.push_back(name + ": no intervals: the " + std::to_string(out.sobol.back().groups_used) +
                           " complete groups are too few to resample (at least " +
                           std::to_string(kMinBootstrapSobolGroups) + "); use more samples" +
                           impossible_indices_note(out.sobol.back(), labels));
  else if (!sobol && study.morris.bootstrap_resamples > 0 && !out.morris.back().has_intervals)
    out.warnings.push_back(name + ": no intervals: the " + std::to_string(out.morris.back().trajectories_used) +
                           " complete trajectories are too few to resample (at least " +
                           std::to_string(kMinBootstrapMorrisTrajectories) + "); use more trajectories");
  else if (sobol)
    for (std::string& w : sobol_warnings(name, out.sobol.back(), labels, study.layout.base_samples))
      out.warnings.push_back(std::move(w));
}

// Method pce: any space-filling design of the study core, and the "pce" settings.
// The design's size: --samples when given (checked by `check`, which blames
// the flag), else the file's "samples", a whole number from `min` to 1e7.
int design_size(const io::JsonReader& d, const DesignOverrides& o, int min) {
  const double n = d.number("samples");  // read even when overridden: a key of the file
  if (o.samples) return static_cast<int>(*o.samples);
  if (!(n >= min && n <= 1e7 && n == std::floor(n)))
    d.fail("samples", "must be a whole number from " + std::to_string(min) + " to 1e7");
  return static_cast<int>(n);
}

// Method pce: any space-filling design of the study core, and the "pce" settings.
void load_pce_design(const io::JsonReader& r, const io::JsonReader& d, const DesignOverrides& o,
                     SensitivityStudy& s, double confidence) {
  std::string type = d.string_or("type", "latin_hypercube");
  if (type == "lhs") type = "latin_hypercube";
  if (type != "latin_hypercube" && type != "sobol" && type != "monte_carlo")
    d.fail("type", "a PCE analysis takes a \"latin_hypercube\" (\"lhs\"), \"sobol\" or \"monte_carlo\" design");
  s.spec.design.type = design_type_from_name(type);
  const int n = design_size(d, o, 1);
  s.pce = parse_pce_options(r, confidence, s.spec.design.seed);
  const int needed = min_pce_sensitivity_runs(s.spec, s.pce);
  if (n < needed) {
    const std::string problem = "a PCE of " + std::to_string(s.spec.inputs.size()) + " inputs needs at least " +
                                std::to_string(needed) + " runs";
    if (o.samples) throw std::invalid_argument("--samples " + std::to_string(n) + ": " + problem);
    d.fail("samples", problem);
  }
  s.spec.design.samples = n;
  if (r.has("second_order")) r.fail("second_order", "applies to the pick-freeze Sobol' method only");
  s.spec.fingerprint = extend_fingerprint(
      s.spec.fingerprint, "pce " + std::to_string(s.pce.settings.max_degree) + " " +
                              std::to_string(s.pce.settings.q_norm) + " " + std::to_string(s.pce.bootstrap));
  s.spec.fingerprint = with_setting(s.spec.fingerprint, "--samples", std::to_string(n), o.samples.has_value());
}

// What the next run of a study refused for too many failed units can do with
// its kept runs: max_failed_fraction is read by the analysis only (it is no
// part of the runs' key), so raising it lets --resume reuse them, unless
// fewer units than the analysis needs (`min_complete`) came through whole.
std::string failed_runs_next_step(int failed_units, int units, int min_complete, const std::string& unit_name) {
  const double least = std::ceil(100.0 * failed_units / units) / 100.0;
  const std::string restart = "remove the cause of the failures and start afresh with --restart (which discards them)";
  if (units - failed_units < min_complete)
    return "no max_failed_fraction can make them usable: " + std::to_string(units - failed_units) + " of " +
           std::to_string(units) + " " + unit_name + " came through whole, and the analysis needs at least " +
           std::to_string(min_complete) + ": " + restart;
  if (!(least < 1.0)) return "no analysis can use them (max_failed_fraction must stay below 1): " + restart;
  return "a --resume of the same study would refuse them again: raise \"max_failed_fraction\" in the study file to " +
         fixed_text(least, 2) + " or more (only the analysis reads it) and --resume reuses them, or " + restart;
}

// The fewest whole units (pick-freeze groups, trajectories, runs) the
// study's analysis needs.
int min_complete_units(const SensitivityStudy& study) {
  switch (study.method) {
    case SensitivityMethod::kSobol: return kMinCompleteSobolGroups;
    case SensitivityMethod::kMorris: return kMinMorrisTrajectories;
    case SensitivityMethod::kPce: return min_pce_sensitivity_runs(study.spec, study.pce);
  }
  return 1;
}

// The bootstrap resamples and confidence of the indices' intervals, checked
// (a PCE study checks its own resamples, from "pce").
struct IndexIntervals {
  int bootstrap = 1000;
  double confidence = 0.95;
};
IndexIntervals read_index_intervals(const io::JsonReader& r, SensitivityMethod method) {
  IndexIntervals out;
  const io::IntegerRange resamples{0, kMaxBootstrap,
                                   "0 (no intervals), or from " + std::to_string(kMinBootstrap) + " to " +
                                       std::to_string(kMaxBootstrap)};
  out.bootstrap = r.integer_or("bootstrap", out.bootstrap, resamples);
  if (out.bootstrap > 0 && out.bootstrap < kMinBootstrap) r.fail("bootstrap", io::whole_number_rule(resamples));
  out.confidence = r.number_or("confidence", out.confidence);
  if (!(out.confidence > 0.5 && out.confidence < 1.0)) r.fail("confidence", "must lie in (0.5, 1)");
  if (method != SensitivityMethod::kPce && out.bootstrap > 0)
    if (const std::string problem = bootstrap_resolution_problem(out.confidence, "'confidence'", out.bootstrap,
                                                                 "'bootstrap'", kMaxBootstrap);
        !problem.empty())
      r.fail("confidence", problem);
  return out;
}

}  // namespace

// The share of Morris trajectories of this design that would draw a value
// the model refuses: every run of every trajectory is set up (no
// simulation), as the study itself would, and a trajectory fails with any of
// its runs.
double morris_refused_share(const SensitivityStudy& s) {
  if (!s.spec.rover) return 0.0;
  const DesignMatrix x = sensitivity_design(s);
  const Eigen::Index runs_per_trajectory = static_cast<Eigen::Index>(varied_count(s.spec)) + 1;
  int failed = 0;
  for (int t = 0; t < s.trajectories; ++t) {
    for (Eigen::Index k = 0; k < runs_per_trajectory; ++k) {
      const Eigen::RowVectorXd row = x.row(t * runs_per_trajectory + k);
      try {
        (void)s.spec.rover->setup_at(row.data());
      } catch (const std::exception&) {
        ++failed;
        break;
      }
    }
  }
  return static_cast<double>(failed) / s.trajectories;
}

// A PCE run fails with its sample, a share p in refused distribution tails;
// a Sobol' pick-freeze group with either of its two independent draws
// (matrices A and B), 1 - (1 - p)^2; a Morris trajectory with any of its
// few runs, each set up here (morris_refused_share). Beyond max_failed_fraction the study would be
// refused after its runs: refused now.
void refuse_failures_beyond_the_limit(const io::JsonReader& r, const SensitivityStudy& s) {
  const double p = s.spec.refused_share;
  double share = p;
  std::string units = "runs", why = s.spec.warnings.empty() ? "" : s.spec.warnings.front();
  if (s.method == SensitivityMethod::kSobol) {
    share = 1.0 - (1.0 - p) * (1.0 - p);
    units = "pick-freeze groups";
    why = "each draws every input twice; " + fixed_text(100.0 * p, 1) + " % of the samples: " + why;
  } else if (s.method == SensitivityMethod::kMorris) {
    share = morris_refused_share(s);
    units = "trajectories";
    why = "set up from this design's levels" + (why.empty() ? "" : ": " + why);
  }
  if (!(share > s.max_failed_fraction)) return;
  r.fail("max_failed_fraction", "is " + fixed_text(s.max_failed_fraction, 2) + ", but about " +
                                    fixed_text(100.0 * share, 1) + " % of the " + units +
                                    " would draw a value the model refuses (" + why +
                                    "): the study would fail after its runs; truncate the distributions");
}

SensitivityStudy load_sensitivity_study(const std::string& path, const DesignOverrides& overrides) {
  const io::Json json = io::read_config_file(path, io::ConfigKind::kStudy);
  const io::JsonReader r(json, path);
  SensitivityStudy s;
  s.spec = parse_study_spec(r, {"sensitivity"}, DesignKey::kByCaller);
  if (s.spec.inputs.size() < 2) r.fail("parameters", "a sensitivity analysis needs at least 2 uncertain inputs");
  for (const UncertainInput& in : s.spec.inputs)
    if (in.distribution.kind == DistributionKind::kFixed)
      r.fail("parameters", "'" + in.label + "' is fixed: a sensitivity analysis varies every input it lists");
  if (s.spec.model->qoi_names().empty() && s.spec.model->channel_names().empty())
    r.fail("qoi", "name at least one QoI or channel");
  const std::string method = r.string("method");
  if (method == "sobol") {
    s.method = SensitivityMethod::kSobol;
  } else if (method == "morris") {
    s.method = SensitivityMethod::kMorris;
  } else if (method == "pce") {
    s.method = SensitivityMethod::kPce;
  } else {
    r.fail("method", "expected \"sobol\", \"morris\" or \"pce\", got \"" + method + "\"");
  }
  if (s.method == SensitivityMethod::kPce && r.has("bootstrap"))
    r.fail("bootstrap", "a PCE study takes its resamples from \"pce\": {\"bootstrap\": n}");
  const auto [bootstrap, confidence] = read_index_intervals(r, s.method);
  s.max_failed_fraction = r.number_or("max_failed_fraction", 0.05);
  if (!(s.max_failed_fraction >= 0.0 && s.max_failed_fraction < 1.0))
    r.fail("max_failed_fraction", "must lie in [0, 1)");
  const io::JsonReader d = r.child("design");
  s.spec.design.seed = d.seed_or("seed", 1);
  const int d_inputs = varied_count(s.spec);
  if (overrides.samples && s.method == SensitivityMethod::kMorris)
    throw std::invalid_argument("--samples sets the Sobol' base sample count or the PCE runs; a Morris study has "
                                "trajectories");
  if (s.method == SensitivityMethod::kPce) {
    load_pce_design(r, d, overrides, s, confidence);
  } else if (s.method == SensitivityMethod::kSobol) {
    const std::string type = d.string_or("type", "sobol");
    if (type != "sobol" && type != "monte_carlo")
      d.fail("type", "the base matrices of a Sobol' analysis come from \"sobol\" or \"monte_carlo\"");
    s.spec.design.type = design_type_from_name(type);
    s.layout.base_samples = design_size(d, overrides, 2);
    s.spec.fingerprint = with_setting(s.spec.fingerprint, "--samples", std::to_string(s.layout.base_samples),
                                      overrides.samples.has_value());
    if (s.spec.design.type == DesignType::kSobol)
      if (std::string w = sobol_balance_warning(static_cast<std::uint64_t>(s.layout.base_samples), "base points");
          !w.empty())
        s.spec.warnings.push_back(std::move(w));
    s.layout.dimensions = d_inputs;
    s.layout.second_order = r.boolean_or("second_order", false);
    s.spec.design.samples = s.layout.total_runs();
    const std::string estimator = r.string_or("estimator", "saltelli_jansen");
    if (estimator == "saltelli_jansen") s.sobol.estimator = SobolEstimator::kSaltelliJansen;
    else if (estimator == "martinez") s.sobol.estimator = SobolEstimator::kMartinez;
    else r.fail("estimator", "expected \"saltelli_jansen\" or \"martinez\"");
    s.sobol.bootstrap_resamples = bootstrap;
    s.sobol.confidence = confidence;
    s.sobol.seed = s.spec.design.seed;
  } else {
    s.trajectories = d.integer("trajectories", {kMinStudyTrajectories, kMaxStudyTrajectories});
    const io::IntegerRange levels{kMinMorrisLevels, kMaxMorrisLevels,
                                  "that is even, from " + std::to_string(kMinMorrisLevels) + " to " +
                                      std::to_string(kMaxMorrisLevels)};
    s.levels = d.integer_or("levels", kDefaultMorrisLevels, levels);
    if (s.levels % 2 != 0) d.fail("levels", io::whole_number_rule(levels));
    if (const double distinct = distinct_morris_steps(d_inputs, s.levels); s.trajectories > distinct)
      d.fail("trajectories", std::to_string(s.trajectories) + " trajectories, but " + std::to_string(d_inputs) +
                                 " input(s) on " + std::to_string(s.levels) + " levels give each input only " +
                                 number_text(distinct) + " distinct steps (a repeated step repeats an elementary effect); " +
                                 "at most " + number_text(distinct) + " trajectories are possible: ask for " +
                                 "fewer, or for more \"levels\"");
    s.spec.design.samples = s.trajectories * (d_inputs + 1);
    s.morris.bootstrap_resamples = bootstrap;
    s.morris.confidence = confidence;
    s.morris.seed = s.spec.design.seed;
    if (r.has("second_order")) r.fail("second_order", "applies to the Sobol' method only");
    if (r.has("channels") && !(r.raw("channels").is_array() && r.raw("channels").empty()))
      r.fail("channels", "curves along time get indices from the \"sobol\" and \"pce\" methods; \"morris\" "
                         "screens the QoIs only");
  }
  d.finish();
  r.finish();
  refuse_failures_beyond_the_limit(r, s);
  s.spec.fingerprint = extend_fingerprint(s.spec.fingerprint, "sensitivity");
  return s;
}

DesignMatrix sensitivity_design(const SensitivityStudy& study) {
  const StudySpec& spec = study.spec;
  const int d = varied_count(spec);
  DesignMatrix unit;
  if (study.method == SensitivityMethod::kPce) {
    unit = unit_design(spec.design.type, spec.design.samples, d, spec.design.seed);
  } else if (study.method == SensitivityMethod::kSobol) {
    const DesignMatrix base = unit_design(spec.design.type, study.layout.base_samples, 2 * d, spec.design.seed);
    const DesignMatrix A = base.leftCols(d), B = base.rightCols(d);
    unit = pick_freeze_design(A, B, study.layout.second_order);
  } else {
    unit = morris_design(d, study.trajectories, study.levels, spec.design.seed).points;
  }
  const bool morris = study.method == SensitivityMethod::kMorris;
  DesignMatrix x(unit.rows(), unit.cols());
  for (Eigen::Index j = 0; j < unit.cols(); ++j) {
    const Distribution& dist = spec.inputs[static_cast<std::size_t>(j)].distribution;
    const bool unbounded = !std::isfinite(dist.support_lower()) || !std::isfinite(dist.support_upper());
    for (Eigen::Index i = 0; i < unit.rows(); ++i)
      x(i, j) = dist.quantile(morris && unbounded ? morris_centred_level(unit(i, j), study.levels) : unit(i, j));
  }
  return x;
}

SensitivityResult analyse_sensitivity(const SensitivityStudy& study, const DesignMatrix& x,
                                      const std::vector<RunRecord>& records) {
  const StudyModel& model = *study.spec.model;
  const RecordLayout layout = model.layout();
  const auto runs = static_cast<Eigen::Index>(records.size());
  const std::vector<std::string> labels = input_labels(study.spec);
  SensitivityResult out;
  out.qoi.assign(static_cast<std::size_t>(layout.qoi_count), std::vector<double>(records.size()));
  for (std::size_t i = 0; i < records.size(); ++i) {
    const RunRecord& r = records[i];
    out.status.push_back(r.status);
    out.messages.push_back(r.message);
    out.failed_runs += r.ok() ? 0 : 1;
    for (int q = 0; q < layout.qoi_count; ++q)
      out.qoi[static_cast<std::size_t>(q)][i] = r.ok() ? r.qoi[static_cast<std::size_t>(q)] : std::nan("");
  }
  out.failure_report = failure_report(study.spec, x, out.status);
  for (std::size_t q = 0; q < out.qoi.size(); ++q)
    if (std::string w = qoi_values_warning(study.spec, q, out.qoi[q]); !w.empty()) out.warnings.push_back(std::move(w));

  // Whole groups / trajectories fail together; more than the stated fraction stops the study.
  const int per_unit = study.method == SensitivityMethod::kSobol  ? study.layout.runs_per_group()
                       : study.method == SensitivityMethod::kMorris ? varied_count(study.spec) + 1
                                                                    : 1;
  const int units = static_cast<int>(records.size()) / per_unit;
  int failed_units = 0;
  for (int g = 0; g < units; ++g) {
    bool failed = false;
    for (int k = 0; k < per_unit; ++k) failed = failed || !records[static_cast<std::size_t>(g * per_unit + k)].ok();
    failed_units += failed ? 1 : 0;
  }
  const char* unit_name = study.method == SensitivityMethod::kSobol    ? "pick-freeze groups"
                          : study.method == SensitivityMethod::kMorris ? "trajectories"
                                                                       : "runs";
  if (failed_units > study.max_failed_fraction * units)
    throw RunsRefused(std::to_string(failed_units) + " of " + std::to_string(units) + " " + unit_name +
                          (study.method == SensitivityMethod::kPce ? " failed" : " have a failed run") +
                          ", more than max_failed_fraction = " + fixed_text(study.max_failed_fraction, 2) +
                          "; the indices would not describe the model. " + out.failure_report,
                      failed_runs_next_step(failed_units, units, min_complete_units(study), unit_name));
  out.too_few_whole_units = units - failed_units < min_complete_units(study);
  if (failed_units > 0)
    out.warnings.push_back(std::to_string(failed_units) + " of " + std::to_string(units) + " " + unit_name +
                           (study.method == SensitivityMethod::kPce ? " failed and were left out of the PCE"
                                                                    : " were dropped whole because a run failed") +
                           " (see /samples/status)");
  if (study.method == SensitivityMethod::kPce) {
    out.pce = analyse_pce_sensitivity(study.spec, study.pce, x, records);
    out.warnings.insert(out.warnings.end(), out.pce.warnings.begin(), out.pce.warnings.end());
    return out;
  }

  const MorrisDesign morris = study.method == SensitivityMethod::kMorris
                                  ? morris_design(varied_count(study.spec), study.trajectories, study.levels,
                                                  study.spec.design.seed)
                                  : MorrisDesign{};
  for (int q = 0; q < layout.qoi_count; ++q)
    estimate_qoi_indices(study, morris, model.qoi_names()[static_cast<std::size_t>(q)], labels,
                         out.qoi[static_cast<std::size_t>(q)], out);
  if (study.method == SensitivityMethod::kSobol)
    for (int c = 0; c < layout.channel_count; ++c) {
      Eigen::MatrixXd Y(runs, layout.time_samples);
      for (Eigen::Index i = 0; i < runs; ++i) {
        const double* curve = records[static_cast<std::size_t>(i)].curve(c, layout.time_samples);
        for (int k = 0; k < layout.time_samples; ++k) Y(i, k) = curve[k];
      }
      out.sobol_t.push_back(estimate_sobol_indices_along_time(study.layout, Y, study.sobol.estimator));
      const std::string& channel = model.channel_names()[static_cast<std::size_t>(c)];
      if (!out.sobol_t.back().aggregated_ST.allFinite()) {
        out.undefined.push_back({channel, "the channel does not vary over the runs: its variance along time is zero"});
        out.warnings.push_back(channel + ": indices along time undefined: " + out.undefined.back().reason);
      } else if (const long long flat = undefined_time_count(out.sobol_t.back()); flat > 0) {
        out.warnings.push_back(channel + ": indices along time undefined (NaN) at " + std::to_string(flat) + " of " +
                               std::to_string(layout.time_samples) + " times, where every run has the same value " +
                               "(before a contact, say); attribute undefined_times of /indices_t/" + channel + "/S1");
      }
    }
  return out;
}


const char* sensitivity_method_name(SensitivityMethod m) {
  return m == SensitivityMethod::kSobol ? "sobol" : m == SensitivityMethod::kMorris ? "morris" : "pce";
}

MemoryEstimate sensitivity_memory(const SensitivityStudy& study) {
  const StudySpec& spec = study.spec;
  const RecordLayout layout = spec.model->layout();
  return {"run records (" + std::to_string(spec.design.samples) + " runs with " +
              std::to_string(layout.channel_count) + " curves of " + std::to_string(layout.time_samples) +
              " samples)",
          static_cast<double>(sizeof(double)) * spec.design.samples * static_cast<double>(layout.value_count() + spec.inputs.size()) *
              kRecordOverhead};
}

SensitivityResult run_sensitivity(const SensitivityStudy& study, const StudyRuntime& runtime) {
  const StudyModel& model = *study.spec.model;
  const RecordLayout layout = model.layout();
  const DesignMatrix x = sensitivity_design(study);
  std::vector<RunRecord> records;
  if (world_rank() == 0) records.reserve(static_cast<std::size_t>(x.rows()));
  auto compute = [&](int i) { return encode_record(i, model.run(x.row(i).data())); };
  auto consume = [&](TaskResult&& task) { records.push_back(decode_record(layout, std::move(task))); };
  const auto started = std::chrono::steady_clock::now();
  stream_study_tasks(static_cast<int>(x.rows()), compute, consume, runtime.options);
  if (world_rank() != 0) return {};
  const double runs_s = seconds_since(started);
  const auto analysis_start = std::chrono::steady_clock::now();
  SensitivityResult result = analyse_sensitivity(study, x, records);
  result.analysis_wall_time_s = seconds_since(analysis_start);
  result.runs_wall_time_s = runs_s;
  result.study = study;
  result.inputs = x;
  return result;
}

bool no_index_for_want_of_runs(const SensitivityResult& result) {
  const std::size_t estimated = result.sobol.size() + result.morris.size() + result.sobol_t.size();
  return result.too_few_whole_units && estimated > 0 && result.undefined.size() >= estimated;
}

StudyProgram<SensitivityResult> sensitivity_program(SensitivityStudy study) {
  const StudySpec& spec = study.spec;
  static constexpr const char* kMethodTitle[] = {"Sobol'", "Morris", "polynomial chaos"};
  StudyProgram<SensitivityResult> p;
  p.command = "sensitivity";
  p.name = spec.name;
  p.fingerprint = spec.fingerprint;
  p.inputs = spec.files;
  p.banner = std::string(kMethodTitle[static_cast<int>(study.method)]) + ", " + std::to_string(spec.inputs.size()) +
             " inputs, " + std::to_string(spec.design.samples) + " runs of " + runs_description(spec) + " on " +
             std::to_string(world_size()) + " rank(s)";
  p.warnings = spec.warnings;
  p.memory = sensitivity_memory(study);
  p.run = [study](const StudyRuntime& runtime) { return run_sensitivity(study, runtime); };
  p.provenance = [spec = study.spec](io::Hdf5Writer& h5) { write_study_provenance(h5, spec, spec.fingerprint); };
  p.write = write_sensitivity;
  p.counts = [](const SensitivityResult& r) { return count_runs(r.status, r.messages); };
  p.report = report_sensitivity;
  p.plot = plot_sensitivity;
  p.figures = [study](PlotSelection plots) { return sensitivity_figures(study, plots); };
  // No indices for want of runs, or indices of a PCE not to be trusted: a result not to use as it is.
  p.verdict = [](const SensitivityResult& r) {
    return no_index_for_want_of_runs(r) || pce_indices_not_to_trust(r.pce) ? kNoIndicesStatus : 0;
  };
  return p;
}

}  // namespace rover::study
