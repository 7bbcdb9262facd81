// See surrogate_spec.hpp.
#include "study/studies/surrogate_spec.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/number_text.hpp"
#include "core/name_list.hpp"
#include "io/config_kind.hpp"
#include "io/hdf5_file.hpp"
#include "io/scenario_config.hpp"
#include "study/studies/surrogate_file.hpp"
#include "study/studies/surrogate_training.hpp"

namespace rover::study {
namespace {

constexpr double kDefaultConfidence = 0.95;
constexpr int kMaxGaussianProcessStarts = 100;
constexpr double kMaxGaussianProcessNugget = 0.1;

// A design without "type" is a Latin hypercube; "lhs" is its alias.
void default_design_type(io::Json& json) {
  if (!json.is_object() || !json.contains("design") || !json["design"].is_object()) return;
  io::Json& design = json["design"];
  if (!design.contains("type")) design["type"] = "latin_hypercube";
  if (design["type"] == "lhs") design["type"] = "latin_hypercube";
}

void check_inputs(const io::JsonReader& r, const StudySpec& spec) {
  if (spec.inputs.empty()) r.fail("parameters", "a surrogate needs at least one uncertain input");
  for (const UncertainInput& in : spec.inputs)
    if (in.distribution.kind == DistributionKind::kFixed)
      r.fail("parameters", "'" + in.label + "' is fixed: every input of a surrogate varies");
}

// Curves need a polynomial chaos and runs made now.
void check_channels(const io::JsonReader& r, const SurrogateStudy& s) {
  if (!r.has("channels") || (r.raw("channels").is_array() && r.raw("channels").empty())) return;  // [] asks for none
  if (s.kind != SurrogateKind::kPolynomialChaos)
    r.fail("channels", "curves along time get a polynomial chaos surrogate: use \"surrogate\": \"pce\"");
  if (!s.training_file.empty())
    r.fail("channels", "curves along time are fitted on a design's runs, not on \"training\" files");
}

// The HDF5 result named by `file` in `r`; `holds` says which results are
// read there ("runs of rover montecarlo, ..."), for a file that is none
// (an evaluate CSV, say).
std::string existing_file(const io::JsonReader& r, const std::string& study_path, const std::string& holds) {
  const std::string file = io::resolve_relative(study_path, r.string("file"));
  if (const std::string problem = io::input_path_problem(file, "a result file"); !problem.empty())
    r.fail("file", file + ": " + problem);
  if (!io::is_hdf5_file(file))
    r.fail("file", file + " is not an HDF5 file; give the .h5 result of " + holds +
                       " (a CSV keeps no input names or provenance)");
  return file;
}

const std::string kRunsResults = "rover montecarlo, evaluate, sensitivity or surrogate, whose runs are read";

GaussianProcessSettings parse_gp_options(const io::JsonReader& r, std::uint64_t seed) {
  GaussianProcessSettings gp;
  gp.seed = seed;
  if (!r.has("gp")) return gp;
  const io::JsonReader g = r.child("gp");
  const std::string trend = g.string_or("trend", "constant");
  if (trend == "linear") gp.trend = KrigingTrend::kLinear;
  else if (trend != "constant") g.fail("trend", "expected \"constant\" or \"linear\", got \"" + trend + "\"");
  gp.starts = g.integer_or("starts", gp.starts, {1, kMaxGaussianProcessStarts});
  if (g.has("nugget") && g.raw("nugget").is_string()) {
    const std::string nugget = g.string("nugget");
    if (nugget != "estimate") g.fail("nugget", "expected a number in [0, 0.1] or \"estimate\", got \"" + nugget + "\"");
    gp.estimate_nugget = true;
  } else {
    gp.nugget = g.number_or("nugget", gp.nugget);
    if (!(gp.nugget >= 0.0 && gp.nugget <= kMaxGaussianProcessNugget)) g.fail("nugget", "must lie in [0, 0.1]");
  }
  gp.q2_threshold = g.number_or("q2_threshold", gp.q2_threshold);
  if (!(gp.q2_threshold > 0.0 && gp.q2_threshold <= 1.0)) g.fail("q2_threshold", "must lie in (0, 1]");
  g.finish();
  return gp;
}

void parse_held_out(const io::JsonReader& r, SurrogateStudy& s) {
  if (!r.has("held_out")) return;
  const io::JsonReader h = r.child("held_out");
  if (h.has("fraction") == h.has("file"))
    r.fail("held_out", "give {\"fraction\": f} (the last runs) or {\"file\": \"result.h5\"}");
  if (h.has("file")) {
    s.held_out_file = existing_file(h, r.file(), kRunsResults);
  } else {
    s.held_out_fraction = h.number("fraction");
    if (!(s.held_out_fraction > 0.0 && s.held_out_fraction <= kMaxHeldOutFraction))
      h.fail("fraction", "must lie in (0, 0.5]");
  }
  h.finish();
}

// The runs of a training file, read before anything runs: their inputs,
// QoIs, scenario and rover as read_result_runs checks them, and the
// successful runs cover the support of every uniform or log-uniform input
// (support_coverage_problem), or the surrogate would extrapolate.
void check_training_runs(const io::JsonReader& t, const SurrogateStudy& s) {
  TrainingRuns runs;
  try {
    runs = read_result_runs(s.training_file, s, "training");
  } catch (const std::exception& e) {
    t.fail("file", e.what());
  }
  std::vector<Eigen::Index> ok;
  for (Eigen::Index i = 0; i < runs.x.rows(); ++i)
    if (runs.status[static_cast<std::size_t>(i)] == run_status::kOk) ok.push_back(i);
  if (const int needed = min_training_runs(s); static_cast<int>(ok.size()) < needed)
    t.fail("file", s.training_file + ": " + std::to_string(ok.size()) + " successful training runs (" +
                       std::to_string(runs.x.rows() - static_cast<Eigen::Index>(ok.size())) + " failed); a " +
                       surrogate_kind_name(s.kind) + " of " + std::to_string(s.spec.inputs.size()) +
                       " inputs needs at least " + std::to_string(needed));
  std::string problems;
  for (std::size_t j = 0; j < s.spec.inputs.size(); ++j) {
    Eigen::VectorXd values(static_cast<Eigen::Index>(ok.size()));
    for (std::size_t k = 0; k < ok.size(); ++k)
      values(static_cast<Eigen::Index>(k)) = runs.x(ok[k], static_cast<Eigen::Index>(j));
    const UncertainInput& in = s.spec.inputs[j];
    const std::string p = support_coverage_problem(in.label, in.distribution, values);
    if (!p.empty()) problems += (problems.empty() ? "" : "; ") + p;
  }
  if (!problems.empty()) t.fail("file", s.training_file + ": " + problems);
}

// A held-out Q2 needs kMinHeldOutRuns runs (surrogate_validation.hpp): a
// held-out file or a fraction of the design that holds fewer is refused
// before any run. A fraction of a training file is checked when it is read.
void check_held_out_runs(const io::JsonReader& r, const SurrogateStudy& s) {
  if (!r.has("held_out")) return;
  const io::JsonReader h = r.child("held_out");
  if (!s.held_out_file.empty()) {
    std::error_code error;
    if (!s.training_file.empty() && std::filesystem::equivalent(s.held_out_file, s.training_file, error))
      h.fail("file", s.held_out_file + " is the training file " + s.training_file +
                         ": a held-out Q2 needs runs the surrogate was not fitted to");
    Eigen::Index runs = kMinHeldOutRuns;
    try {
      const io::Hdf5Reader h5(s.held_out_file);
      if (h5.exists("/inputs/values")) runs = h5.read_matrix("/inputs/values").rows();
    } catch (const std::exception& e) {
      h.fail("file", e.what());
    }
    if (runs < kMinHeldOutRuns)
      h.fail("file", s.held_out_file + " holds " + std::to_string(runs) + " run(s); a held-out Q2 needs at least " +
                         std::to_string(kMinHeldOutRuns));
    TrainingRuns held_out;
    try {  // its inputs, QoIs, scenario and rover: before any run, not after them
      held_out = read_result_runs(s.held_out_file, s, "held-out");
    } catch (const std::exception& e) {
      h.fail("file", e.what());
    }
    // Runs the surrogate will be fitted to, found now: the design is a
    // function of its seed, a training file is read already.
    TrainingRuns training;
    if (s.training_file.empty()) {
      training.x = study_design(s.spec);
    } else {
      try {
        training = read_result_runs(s.training_file, s, "training");
      } catch (const std::exception&) {  // named by check_training_runs
      }
    }
    if (const std::string shared = shared_runs(training, held_out); !shared.empty()) h.fail("file", shared);
  } else if (s.training_file.empty() && s.held_out_runs() < kMinHeldOutRuns) {
    h.fail("fraction", held_out_count_problem(s.held_out_fraction, s.spec.design.samples));
  }
}

// A "compare" file without the total indices of any QoI is refused before
// any run; one without some QoIs' indices is warned of then.
void check_compare_file(const io::JsonReader& c, SurrogateStudy& s) {
  std::vector<std::string> missing;
  try {
    missing = qois_without_compared_indices(s);
    if (const std::string unchecked = check_result_provenance(s.compare_file, s, "compared"); !unchecked.empty())
      s.spec.warnings.push_back("'compare.file': " + unchecked);
  } catch (const std::exception& e) {
    c.fail("file", e.what());
  }
  if (missing.empty()) return;
  std::vector<std::string> inputs;
  for (const UncertainInput& in : s.spec.inputs) inputs.push_back(in.label);
  const std::string lacks = s.compare_file + " has no total indices of " + comma_separated(missing) +
                            " over the study's inputs (" + comma_separated(inputs) + ")";
  if (missing.size() == s.qoi_names().size())
    c.fail("file", lacks + ": give the result of rover sensitivity (Sobol') of these QoIs over these inputs");
  s.spec.warnings.push_back("'compare.file': " + lacks + ": they are compared with nothing");
}

void check_design_runs(const io::JsonReader& r, const SurrogateStudy& s) {
  const int training = s.spec.design.samples - s.held_out_runs();
  const int needed = min_training_runs(s);
  if (training < needed)
    r.child("design").fail("samples", std::to_string(training) + " training runs (" +
                                          std::to_string(s.held_out_runs()) + " held out); a " +
                                          surrogate_kind_name(s.kind) + " of " +
                                          std::to_string(s.spec.inputs.size()) + " inputs needs at least " +
                                          std::to_string(needed));
}

}  // namespace

std::string held_out_count_problem(double fraction, long long runs) {
  const long long held_out = std::llround(fraction * static_cast<double>(runs));
  if (held_out >= kMinHeldOutRuns) return "";
  return number_text(fraction) + " of " + std::to_string(runs) + " runs holds out " + std::to_string(held_out) +
         (held_out == 1 ? " run" : " runs") + "; a held-out Q2 needs at least " + std::to_string(kMinHeldOutRuns) +
         " (a fraction of at least " + number_text((kMinHeldOutRuns - 0.5) / static_cast<double>(runs)) +
         " of these runs, or more runs)";
}

double SurrogateStudy::q2_threshold() const {
  return kind == SurrogateKind::kPolynomialChaos ? pce.settings.q2_threshold : gp.q2_threshold;
}

std::vector<std::string> SurrogateStudy::qoi_names() const { return spec.model->qoi_names(); }

std::vector<Distribution> SurrogateStudy::distributions() const {
  std::vector<Distribution> d;
  for (const UncertainInput& in : spec.inputs) d.push_back(in.distribution);
  return d;
}

int SurrogateStudy::held_out_runs() const {
  if (!training_file.empty()) return 0;
  return static_cast<int>(std::lround(held_out_fraction * spec.design.samples));
}

int min_training_runs(const SurrogateStudy& s) {
  if (s.kind == SurrogateKind::kPolynomialChaos) return min_pce_runs(s.distributions(), s.pce.settings);
  const int trend_terms = s.gp.trend == KrigingTrend::kConstant ? 1 : static_cast<int>(s.spec.inputs.size()) + 1;
  return trend_terms + 2;
}

SurrogateStudy load_surrogate_study(const std::string& path, const DesignOverrides& overrides) {
  io::Json json = io::read_config_file(path, io::ConfigKind::kStudy);
  default_design_type(json);
  const io::JsonReader r(json, path);
  SurrogateStudy s;
  const bool from_file = r.has("training");
  if (from_file && r.has("design"))
    r.fail("design", "give either \"design\" (runs made now) or \"training\" (the runs of a result file)");
  s.spec = parse_study_spec(r, {"surrogate"}, from_file ? DesignKey::kByCaller : DesignKey::kRequired);
  check_inputs(r, s.spec);
  try {
    s.kind = surrogate_kind_from_name(r.string_or("surrogate", "pce"));
  } catch (const std::invalid_argument& e) {
    r.fail("surrogate", e.what());
  }
  const double confidence = r.number_or("confidence", kDefaultConfidence);
  if (!(confidence > 0.5 && confidence < 1.0)) r.fail("confidence", "must lie in (0.5, 1)");
  const std::uint64_t seed = s.spec.design.seed;
  if (s.kind == SurrogateKind::kPolynomialChaos && r.has("gp")) r.fail("gp", "applies to \"surrogate\": \"gp\"");
  if (s.kind == SurrogateKind::kGaussianProcess && r.has("pce")) r.fail("pce", "applies to \"surrogate\": \"pce\"");
  s.pce = parse_pce_options(r, confidence, seed);
  s.gp = parse_gp_options(r, seed);
  if (from_file) {
    const io::JsonReader t = r.child("training");
    s.training_file = existing_file(t, path, kRunsResults);
    t.finish();
    check_training_runs(t, s);
  }
  parse_held_out(r, s);
  check_channels(r, s);
  if (r.has("compare")) {
    const io::JsonReader c = r.child("compare");
    if (s.kind != SurrogateKind::kPolynomialChaos) r.fail("compare", "compares the indices of a polynomial chaos");
    s.compare_file = existing_file(c, path, "rover sensitivity, whose indices are compared");
    check_compare_file(c, s);
    c.finish();
  }
  if (overrides.samples) set_surrogate_runs(s, static_cast<int>(*overrides.samples));  // before the checks of the size
  if (!from_file) check_design_runs(r, s);
  check_held_out_runs(r, s);
  r.finish();
  s.spec.fingerprint = extend_fingerprint(
      s.spec.fingerprint, std::string("surrogate ") + surrogate_kind_name(s.kind) + " " + s.training_file + " " +
                              s.held_out_file + " " + std::to_string(s.held_out_fraction));
  if (!from_file)
    s.spec.fingerprint = with_setting(s.spec.fingerprint, "--samples", std::to_string(s.spec.design.samples),
                                      overrides.samples.has_value());
  return s;
}

std::vector<std::string> qois_without_compared_indices(const SurrogateStudy& study) {
  const io::Hdf5Reader h5(study.compare_file);
  const std::vector<std::string> names =
      h5.exists("/inputs/names") ? h5.read_strings("/inputs/names") : std::vector<std::string>{};
  const bool every_input = std::all_of(study.spec.inputs.begin(), study.spec.inputs.end(), [&](const UncertainInput& in) {
    return std::find(names.begin(), names.end(), in.name) != names.end();
  });
  std::vector<std::string> missing;
  for (const std::string& q : study.qoi_names())
    if (!every_input || !h5.exists("/indices/" + q + "/ST")) missing.push_back(q);
  return missing;
}

void set_surrogate_runs(SurrogateStudy& s, int runs) {
  if (!s.training_file.empty())
    throw std::invalid_argument("--samples sets the runs of a design; this study trains on " + s.training_file);
  if (s.spec.design.type == DesignType::kGrid)
    throw std::invalid_argument("--samples does not apply to a grid design (its size is the product of its levels)");
  if (s.held_out_file.empty() && s.held_out_fraction > 0.0)
    if (const std::string p = held_out_count_problem(s.held_out_fraction, runs); !p.empty())
      throw std::invalid_argument("--samples " + std::to_string(runs) + ": 'held_out.fraction' " + p);
  SurrogateStudy trial = s;
  trial.spec.design.samples = runs;
  const int training = runs - trial.held_out_runs(), needed = min_training_runs(s);
  if (training < needed)
    throw std::invalid_argument("--samples " + std::to_string(runs) + ": " + std::to_string(training) +
                                " training runs; a " + surrogate_kind_name(s.kind) + " of " +
                                std::to_string(s.spec.inputs.size()) + " inputs needs at least " +
                                std::to_string(needed));
  s.spec.design.samples = runs;
}

}  // namespace rover::study
