// See study_spec.hpp.
#include "study/studies/study_spec.hpp"
#include "core/name_list.hpp"
#include "core/accuracy_choice.hpp"

#include <bit>
#include <cmath>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include "core/number_text.hpp"
#include "core/reference_miss.hpp"
#include "core/rover_parameters.hpp"
#include "io/config_kind.hpp"
#include "io/checkpoint.hpp"
#include "io/output_target.hpp"
#include "io/result_label.hpp"
#include "io/csv.hpp"
#include "io/trajectory_io.hpp"
#include "study/model/distribution_json.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/report_number.hpp"

namespace rover::study {
namespace {

int preload_index(const std::string& label) {
  for (int i = 0; i < kNumSJoints; ++i)
    if (label == preload_alias(i) || label == "s_structure." + preload_alias(i)) return i;
  return -1;
}

// "from_config": Normal(preload_mean_i, sd_scale * preload_sd_i), optionally truncated.
Distribution preload_distribution(const io::JsonReader& p, const io::Json& rover, double mean, int i) {
  const double sd_scale = p.has("sd_scale") ? p.non_negative("sd_scale") : 1.0;
  const io::Json& sds = rover.at("s_structure").at("preload_sd");
  const double sd = sd_scale * sds.at(static_cast<std::size_t>(i)).get<double>();
  double lower = -std::numeric_limits<double>::infinity(), upper = std::numeric_limits<double>::infinity();
  if (p.has("truncate")) {
    const io::Json& t = p.raw("truncate");
    if (!t.is_array() || t.size() != 2) p.fail("truncate", "expected [lower, upper] (null for no bound)");
    for (std::size_t k = 0; k < 2; ++k)
      if (!t[k].is_null() && !t[k].is_number())
        p.fail("truncate", "element " + std::to_string(k) + " is neither a number nor null");
    if (!t[0].is_null()) lower = t[0].get<double>();
    if (!t[1].is_null()) upper = t[1].get<double>();
  }
  const Distribution d = sd == 0.0 ? fixed_value(mean) : normal(mean, sd, lower, upper);
  std::string why;
  if (!d.IsValid(&why)) p.fail(p.has("truncate") ? "truncate" : "sd_scale", why);
  return d;
}

// The point the checks below start from: every input at its configured value;
// an optional scenario key the scenario does not set (nominal NaN, such as
// "scenario.initial_q.x") at its distribution's median instead, a value the
// study will give it.
std::vector<double> base_point(const std::vector<UncertainInput>& inputs) {
  std::vector<double> point;
  for (const UncertainInput& in : inputs)
    point.push_back(std::isnan(in.nominal) ? in.distribution.quantile(0.5) : in.nominal);
  return point;
}

// A time this close to the run's end (relative) is the run's end.
constexpr double kRunEndTolerance = 1e-9;

// Relative size of the step that tells whether an input can vary alone.
constexpr double kAloneStep = 1e-6;

// How the checks below name an input's value at the base point: its
// configured value, or the median its distribution gives a key the files
// set no value for.
std::string base_value_text(const UncertainInput& input, double value) {
  if (std::isnan(input.nominal))
    return number_text(value) + ", the median of its " + input.distribution.describe() + " (the files set no value)";
  return "its configured value " + number_text(value);
}

// Refuses a base point the model refuses, naming what was tried: the keys
// the files set no value for, at their medians (initial_u.z uniform on
// [-2000, 0] starts at -1000, beyond the rover's speeds), and the model's
// reason. Every check below starts from that point.
void refuse_a_refused_base_point(const io::JsonReader& r, const RoverStudyModel& model,
                                 const std::vector<UncertainInput>& inputs) {
  const std::vector<double> base = base_point(inputs);
  try {
    (void)model.setup_at(base.data());
    return;
  } catch (const std::exception& e) {
    std::string medians;
    for (std::size_t j = 0; j < inputs.size(); ++j)
      if (std::isnan(inputs[j].nominal))
        medians += (medians.empty() ? "" : ", ") + ("'" + inputs[j].label + "' at " + base_value_text(inputs[j], base[j]));
    if (medians.empty())
      r.fail("parameters", std::string("with every parameter at its configured value, the model refuses the run (") +
                               e.what() + ")");
    r.fail("parameters", "with " + medians + " and every other parameter at its configured value, the model " +
                             "refuses the run (" + e.what() + "): most samples would fail");
  }
}

// Refuses parameters that are all "fixed": every run would be the same run,
// and its bands, summaries or indices would say nothing of uncertainty.
void refuse_nothing_varied(const io::JsonReader& r, const std::vector<UncertainInput>& inputs) {
  if (inputs.empty()) return;
  for (const UncertainInput& in : inputs)
    if (in.distribution.kind != DistributionKind::kFixed) return;
  r.fail("parameters", "every parameter is fixed: each run would be the same run; give at least one a "
                       "distribution (or run it once with rover simulate)");
}

// Refuses, before any run, an input that cannot change while every other
// input keeps its nominal value: an off-diagonal inertia entry, say, whose
// symmetric partner stays put. Such an input fails a step of kAloneStep (of
// its magnitude) either way from its nominal value, which the model takes
// (refuse_a_refused_base_point); an input that is merely at a bound of its
// valid range passes one way. The message names the values tried.
void refuse_inputs_that_cannot_vary_alone(const io::JsonReader& r, const RoverStudyModel& model,
                                          const std::vector<UncertainInput>& inputs) {
  const std::vector<double> nominal = base_point(inputs);
  for (std::size_t j = 0; j < inputs.size(); ++j) {
    if (inputs[j].distribution.kind == DistributionKind::kFixed) continue;
    const double step = kAloneStep * std::max(1.0, std::abs(nominal[j]));
    std::string why;
    bool varies = false;
    for (double sign : {1.0, -1.0}) {
      std::vector<double> x = nominal;
      x[j] += sign * step;
      try {
        (void)model.setup_at(x.data());
        varies = true;
        break;
      } catch (const std::exception& e) {
        why = e.what();
      }
    }
    if (!varies)
      r.fail("parameters", "'" + inputs[j].label + "' cannot vary alone: the model takes it at " +
                               base_value_text(inputs[j], nominal[j]) + " but refuses " +
                               number_text(nominal[j] - step) + " and " + number_text(nominal[j] + step) +
                               ", with every other parameter at its configured value (" + why + ")");
  }
}

// How far inside a bounded support its ends are tried (a continuous
// distribution never draws the end itself: f uniform on [0, 1e5] is fine).
constexpr double kSupportEndInset = 1e-9;

// Refuses a distribution whose median the model refuses (c_q normal(-1,
// 0.1)), or that is no finite number: most of its samples would fail.
void refuse_a_refused_median(const io::JsonReader& r, const RoverStudyModel& model, const std::vector<double>& nominal,
                             std::size_t j, const UncertainInput& input) {
  std::vector<double> x = nominal;
  x[j] = input.distribution.quantile(0.5);
  const std::string head = "'" + input.label + "': the median of its " + input.distribution.describe() + ", " +
                           number_text(x[j]) + ", ";
  if (!std::isfinite(x[j])) r.fail("parameters", head + "is no finite number; most samples would be too");
  try {
    (void)model.setup_at(x.data());
  } catch (const std::exception& e) {
    r.fail("parameters", head + "is refused by the model (" + e.what() + "): most samples would fail");
  }
}

// Refuses, before any run, a distribution whose support reaches values the
// model refuses (with every other input at its nominal value): f uniform up
// to 1e9, say, beyond the S-structure's bound. Every sample there would be a
// failed run found only after the study; unbounded supports are not tried.
void refuse_supports_the_model_refuses(const io::JsonReader& r, const RoverStudyModel& model,
                                       const std::vector<UncertainInput>& inputs) {
  const std::vector<double> nominal = base_point(inputs);
  for (std::size_t j = 0; j < inputs.size(); ++j) {
    const Distribution& d = inputs[j].distribution;
    if (d.kind == DistributionKind::kFixed) continue;
    const double lo = d.support_lower(), hi = d.support_upper();
    for (const double end : {lo, hi}) {
      if (!std::isfinite(end)) continue;
      // Relative to the width of a bounded support, or to the end's own size
      // on a half-bounded one (a lognormal's 0, a one-sided truncation).
      const double inset = kSupportEndInset * (std::isfinite(hi - lo) ? hi - lo : std::max(1.0, std::abs(end)));
      std::vector<double> x = nominal;
      x[j] = end == lo ? end + inset : end - inset;
      try {
        (void)model.setup_at(x.data());
      } catch (const std::exception& e) {
        r.fail("parameters", "'" + inputs[j].label + "': its distribution reaches " + number_text(end) +
                                 ", where the model refuses it; every sample near there would fail (" + e.what() +
                                 "); narrow the distribution");
      }
    }
    refuse_a_refused_median(r, model, nominal, j, inputs[j]);
  }
}

// The smallest tail probability probed, and the bisection steps that find
// where a refused tail begins (to a share of 2^-40 of the probed range).
constexpr double kTailProbe = 1e-6;
constexpr int kTailBisections = 40;
constexpr int kShareDigits = 3;

// The share of input j's samples beyond where the model refuses it, in the
// tail below (lower = true) or above its median; 0 if the model takes the
// tail up to the kTailProbe quantile. `why` receives the model's reason.
double refused_tail_share(const RoverStudyModel& model, const std::vector<double>& nominal, std::size_t j,
                          const Distribution& d, bool lower, std::string* why) {
  const auto refused = [&](double share) {
    std::vector<double> x = nominal;
    x[j] = d.quantile(lower ? share : 1.0 - share);
    try {
      (void)model.setup_at(x.data());
      return false;
    } catch (const std::exception& e) {
      *why = e.what();
      return true;
    }
  };
  if (!refused(kTailProbe)) return 0.0;
  double inside = kTailProbe, outside = 0.5;  // refused at `inside`; taken at `outside` (the median)
  if (refused(outside)) return 0.5;
  for (int i = 0; i < kTailBisections; ++i) {
    const double mid = 0.5 * (inside + outside);
    (refused(mid) ? inside : outside) = mid;
  }
  (void)refused(kTailProbe);  // the reason at the tail's far end
  return outside;
}

// Warns (spec.warnings) of unbounded distribution tails that reach values
// the model refuses (c_q normal(0.05, 0.1) below 0), and sets
// spec.refused_share: those samples are failed runs, and the study's
// statistics cover only the rest. Bounded supports are
// refused outright by refuse_supports_the_model_refuses.
void warn_of_refused_tails(const RoverStudyModel& model, const std::vector<UncertainInput>& inputs, StudySpec& spec) {
  std::vector<std::string>& warnings = spec.warnings;
  double kept_share = 1.0;  // of samples outside every refused tail, the inputs drawn independently
  const std::vector<double> nominal = base_point(inputs);
  for (std::size_t j = 0; j < inputs.size(); ++j) {
    const Distribution& d = inputs[j].distribution;
    for (const bool lower : {true, false}) {
      if (std::isfinite(lower ? d.support_lower() : d.support_upper())) continue;
      std::string why;
      const double share = refused_tail_share(model, nominal, j, d, lower, &why);
      if (share == 0.0) continue;
      kept_share *= 1.0 - share;
      warnings.push_back("'" + inputs[j].label + "': about " + format_number(100.0 * share, kShareDigits) +
                         " % of its " + d.describe() + " samples lie in its " + (lower ? "lower" : "upper") +
                         " tail, where the model refuses them (" + why + "); those runs will fail and the " +
                         "results cover only the rest; \"truncate\": [lower, upper] restricts the distribution");
    }
  }
  spec.refused_share = 1.0 - kept_share;
}

// A truncation that keeps less than this of a distribution's probability
// (beyond about 5 sd) makes of it another distribution, crowded against the
// bound: a mistyped mean or bound, more likely than a wish.
constexpr double kFarTruncationMass = 1e-6;

// Warns (spec.warnings) of truncations far in a distribution's tail.
void warn_of_far_truncations(const std::vector<UncertainInput>& inputs, StudySpec& spec) {
  for (const UncertainInput& in : inputs) {
    const Distribution& d = in.distribution;
    const double mass = d.truncation_mass();
    if (!(mass < kFarTruncationMass)) continue;
    spec.warnings.push_back("'" + in.label + "': its truncation keeps " + format_number(mass, kShareDigits) +
                            " of the untruncated distribution's probability: the samples of " + d.describe() +
                            " crowd against a bound (from " + format_number(d.quantile(0.0 + 1e-12), 6) + " to " +
                            format_number(d.quantile(1.0 - 1e-12), 6) + "), nothing like the distribution " +
                            "without it; is the truncation or the mean mistyped?");
  }
}

std::vector<UncertainInput> parse_rover_parameters_block(const io::JsonReader& r,
                                                         const io::ScenarioSources& sources) {
  std::vector<UncertainInput> inputs;
  const ParameterSpace space(sources.rover, sources.scenario);
  const io::Json& block = r.raw("parameters");
  if (!block.is_object() || block.empty())
    r.fail("parameters", "expected an object {\"<parameter>\": {\"distribution\": ...}, ...}");
  const io::JsonReader params = r.child("parameters");
  std::vector<std::string> entries;  // the key of "parameters" each input came from
  // A parameter given by two keys (an alias and a dotted path, or "M0" and one
  // of its preloads), or two that set a common number (M0_scale and a preload).
  auto refuse_repeat = [&](const std::string& name, const std::string& label) {
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      const std::string of = "'" + entries[k] + "'" +
                             (entries[k] != inputs[k].label ? " (its " + inputs[k].label + ")" : "");
      if (inputs[k].name == name) params.fail(label, "is the same parameter as " + of);
      if (parameters_overlap(inputs[k].name, name))
        params.fail(label, "overlaps " + of + ": " + overlap_reason(inputs[k].name, name));
    }
  };
  for (const auto& [label, spec] : block.items()) {
    const io::JsonReader p = params.child(label);
    const bool from_config = p.boolean_or("from_config", false);
    if (label == "M0" || label == "s_structure.M0") {
      if (!from_config && !p.has("distribution"))
        p.fail("from_config", "the preload group \"M0\" takes its means and sds from the rover file: "
                              "give \"from_config\": true");
      p.string_or("distribution", "normal");
      for (int i = 0; i < kNumSJoints; ++i) {
        const std::string name = space.canonical(preload_alias(i));
        refuse_repeat(name, label);
        inputs.push_back({name, preload_alias(i),
                          preload_distribution(p, sources.rover, space.nominal(name), i),
                          space.nominal(name)});
        entries.push_back(label);
      }
      p.finish();
      continue;
    }
    std::string name;
    try {
      name = space.canonical(label);
    } catch (const std::invalid_argument& e) {
      params.fail(label, e.what());
    }
    if (const std::string why = run_setting_not_parameter(name); !why.empty())
      params.fail(label, why + "; study a model parameter");
    const double nominal = space.nominal(name);
    Distribution d;
    if (from_config) {
      const int i = preload_index(label);
      if (i < 0) p.fail("from_config", "only the preloads (M0, M0_11 .. M0_42) have sds in the rover file");
      p.string_or("distribution", "normal");
      d = preload_distribution(p, sources.rover, nominal, i);
    } else {
      d = parse_distribution(p, nominal);
    }
    std::string why;
    if (!d.IsValid(&why)) p.fail("distribution", why);
    p.finish();
    refuse_repeat(name, label);
    inputs.push_back({name, label, d, nominal});
    entries.push_back(label);
  }
  return inputs;
}

std::vector<UncertainInput> analytic_inputs(const io::JsonReader& r, const AnalyticStudyModel& m) {
  std::vector<UncertainInput> inputs;
  for (std::size_t i = 0; i < m.input_names().size(); ++i) {
    const std::string& x = m.input_names()[i];
    Distribution d = m.name() == "ishigami" ? uniform(-std::numbers::pi, std::numbers::pi)
                     : m.name() == "sobol_g" ? uniform(0.0, 1.0)
                                             : normal(0.0, 1.0);
    inputs.push_back({x, x, d, d.mean()});
  }
  if (!r.has("parameters")) return inputs;
  const io::JsonReader params = r.child("parameters");
  for (const auto& [label, spec] : r.raw("parameters").items()) {
    auto it = std::find_if(inputs.begin(), inputs.end(), [&](const UncertainInput& u) { return u.name == label; });
    if (it == inputs.end())
      params.fail(label, "is not an input of the " + m.name() + " model (" + comma_separated(m.input_names()) + ")");
    const io::JsonReader p = params.child(label);
    it->distribution = parse_distribution(p, it->nominal);
    std::string why;
    if (!it->distribution.IsValid(&why)) p.fail("distribution", why);
    p.finish();
  }
  return inputs;
}

// An rms_vs QoI's "reference" curve (and its "channel" into q): the checks of
// every measured curve, and a declared channel other than the QoI's refused.
std::shared_ptr<ReferenceCurve> parse_rms_reference(const io::JsonReader& o, const std::string& study_path,
                                                    const std::string& qoi_field, QoiSpec& q) {
  auto ref = std::make_shared<ReferenceCurve>();
  ref->path = io::resolve_relative(study_path, o.string("reference"));
  const std::string channel = o.string_or("channel", "B_l_z");
  try {
    q.channel = channel_from_name(channel);
  } catch (const std::invalid_argument& e) {
    o.fail("channel", e.what());
  }
  try {
    if (ref->path.ends_with(".csv")) {
      // The checks of every measured curve (io::read_measured_curve): a
      // height in millimetres is caught; other channels have no bound.
      const double bound = channel.ends_with("_z") ? io::kMeasuredCurveMaxAbsHeight_m
                                                   : std::numeric_limits<double>::infinity();
      const io::MeasuredCurve c = io::curve_from_table(io::read_csv(ref->path, {"t", "z"}), "z", bound);
      ref->t = c.t_s;
      ref->value = c.z_m;
    } else {
      const io::Curve c = io::read_curve(ref->path, channel);
      ref->t = c.t;
      ref->value = c.y;
    }
  } catch (const std::exception& e) {
    o.fail("reference", e.what());
  }
  // A curve whose header declares its channel (rover synthesize) is compared as that channel only.
  if (const std::string declared = io::declared_channel(ref->path); !declared.empty() && declared != channel)
    o.fail("reference", ref->path + ": declares its z to be " + declared + " (its header), but rms_vs compares " +
                            channel + ": give \"channel\": \"" + declared + "\" in " + qoi_field +
                            ", or a curve of " + channel);
  for (std::size_t i = 1; i < ref->t.size(); ++i)
    if (!(ref->t[i] > ref->t[i - 1]))
      o.fail("reference", ref->path + ": times must increase strictly (row " + std::to_string(i + 1) + ")");
  if (ref->t.size() < 3) o.fail("reference", ref->path + ": needs at least 3 samples");
  ref->time_offset_s = o.number_or("time_offset", 0.0);
  return ref;
}

// Why qoi[k] cannot be stored beside qoi[j] under the same `name`: the
// same QoI twice, or a label that repeats another's name or label.
std::string repeated_qoi_name(const io::Json& list, std::size_t j, std::size_t k, const std::string& name) {
  const auto labelled = [&](std::size_t i) { return list[i].is_object() && list[i].contains("label"); };
  if (!labelled(j) && !labelled(k)) return "QoI '" + name + "' appears twice (give one a \"label\")";
  return std::string(labelled(k) ? "its label '" : "its name '") + name + "' is also the " +
         (labelled(j) ? "label" : "name") + " of qoi[" + std::to_string(j) +
         "]: every QoI is stored under its own label; give another";
}

std::vector<QoiSpec> parse_qois(const io::JsonReader& r, const std::string& study_path) {
  std::vector<QoiSpec> qois;
  const io::Json& list = r.raw("qoi");
  if (!list.is_array() || list.empty())
    r.fail("qoi", "expected a list of quantities of interest, e.g. [\"B_l_z_min\", \"deflection\"] (valid: " +
                      comma_separated(qoi_kind_names()) + ")");
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string field = "qoi[" + std::to_string(k) + "]";
    QoiSpec q;
    try {
      if (list[k].is_string()) {
        q.name = list[k].get<std::string>();
        q.kind = qoi_kind_from_name(q.name);
      } else if (list[k].is_object()) {
        const io::JsonReader o(list[k], r.file(), r.field(field));
        const std::string kind = o.string("name");
        try {
          q.kind = qoi_kind_from_name(kind);
        } catch (const std::invalid_argument& e) {
          o.fail("name", e.what());
        }
        q.name = o.string_or("label", kind);
        if (const std::string problem = io::result_label_problem(q.name); !problem.empty()) o.fail("label", problem);
        if (q.kind == QoiKind::kSettlingTime && o.has("band")) {
          q.settling_band = o.positive("band");
          if (q.settling_band > kMaxSettlingBand_m)
            o.fail("band", number_text(q.settling_band) + " m is beyond " + number_text(kMaxSettlingBand_m) +
                               " m, wider than a drop test's travel of a few centimetres: every run would settle "
                               "at once (a band in millimetres?)");
        }
        if (q.kind == QoiKind::kRmsVs) q.reference = parse_rms_reference(o, study_path, r.field(field), q);
        o.finish();
      } else {
        r.fail(field, "expected a QoI name or {\"name\": ...}, got " + list[k].dump());
      }
    } catch (const std::invalid_argument& e) {
      r.fail(field, e.what());
    }
    if (q.kind == QoiKind::kRmsVs && !q.reference)
      r.fail(field, "rms_vs needs a reference: {\"name\": \"rms_vs\", \"reference\": \"curve.csv\"}");
    for (std::size_t j = 0; j < qois.size(); ++j)
      if (qois[j].name == q.name) r.fail(field, repeated_qoi_name(list, j, k, q.name));
    qois.push_back(q);
  }
  return qois;
}

// A reference curve that the run of `scenario` (its duration_s) cannot be
// compared with (reference_span_problem), or a constant curve of heights.
void refuse_references_beside_the_run(const io::JsonReader& r, const std::vector<QoiSpec>& qois,
                                      const std::string& scenario, double duration_s) {
  for (std::size_t k = 0; k < qois.size(); ++k) {
    if (!qois[k].reference) continue;
    const ReferenceCurve& ref = *qois[k].reference;
    const std::string field = "qoi[" + std::to_string(k) + "].reference";
    if (const std::string p = reference_span_problem(ref.t, ref.time_offset_s, duration_s); !p.empty())
      r.fail(field, ref.path + " " + p + " (run: " + scenario + ")");
    if (std::string(channel_name(qois[k].channel)).ends_with("_z"))
      if (const std::string p = constant_reference_problem(ref.value); !p.empty()) r.fail(field, ref.path + ": " + p);
  }
}

std::vector<Channel> parse_channels(const io::JsonReader& r) {
  std::vector<Channel> channels;
  if (!r.has("channels")) return channels;
  const std::vector<std::string> names = [&] {
    const io::Json& list = r.raw("channels");
    if (!list.is_array()) r.fail("channels", "expected a list of channel names (" + comma_separated(channel_names()) + ")");
    std::vector<std::string> n;
    for (const auto& v : list) {
      if (!v.is_string()) r.fail("channels", "expected channel names (" + comma_separated(channel_names()) + ")");
      n.push_back(v.get<std::string>());
    }
    return n;
  }();
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string field = "channels[" + std::to_string(k) + "]";
    try {
      channels.push_back(channel_from_name(names[k]));
    } catch (const std::invalid_argument& e) {
      r.fail(field, e.what());
    }
    if (std::find(names.begin(), names.begin() + static_cast<std::ptrdiff_t>(k), names[k]) !=
        names.begin() + static_cast<std::ptrdiff_t>(k))
      r.fail(field, "channel '" + names[k] + "' appears twice: list each channel once");
  }
  return channels;
}

// The points a grid design may have (and so the levels of one input).
constexpr int kMaxGridPoints = 100'000'000;

// How "levels" is written: one whole number for every varied input, or an
// object naming each one ({"c_q": 3, "f": 2}), shown with the numbers of an
// array given in its place.
std::string grid_levels_form(const std::vector<UncertainInput>& inputs, const io::Json& levels) {
  constexpr int kExampleLevels = 3;
  std::string example;
  std::size_t k = 0;
  for (const UncertainInput& in : inputs) {
    if (in.distribution.kind == DistributionKind::kFixed) continue;
    const bool from_array = levels.is_array() && k < levels.size() && levels[k].is_number();
    const std::string n = from_array ? levels[k].dump() : std::to_string(kExampleLevels);
    example += (example.empty() ? "{" : ", ") + std::string("\"") + in.label + "\": " + n;
    ++k;
  }
  return "give one whole number of levels for every input (\"levels\": " + std::to_string(kExampleLevels) +
         "), or an object naming the levels of each input (\"levels\": " + example + "})";
}

// "300 x 400000" for the levels of a grid.
std::string grid_points_text(const std::vector<int>& levels) {
  std::string text;
  for (const int n : levels)
    if (n > 1) text += (text.empty() ? "" : " x ") + std::to_string(n);
  return text;
}

DesignSpec parse_design(const io::JsonReader& d, const std::vector<UncertainInput>& inputs, int min_samples) {
  DesignSpec spec;
  try {
    spec.type = design_type_from_name(d.string("type"));
  } catch (const std::invalid_argument& e) {
    d.fail("type", e.what());
  }
  if (spec.type == DesignType::kGrid) {
    if (d.has("samples")) d.fail("samples", "a grid's size is the product of its \"levels\"");
    if (d.has("seed")) d.fail("seed", "a grid draws nothing (its points are its levels); remove the seed");
    const io::Json& levels = d.raw("levels");
    std::optional<io::JsonReader> per_input;
    if (levels.is_object()) per_input.emplace(d.child("levels"));
    else if (!levels.is_number()) d.fail("levels", grid_levels_form(inputs, levels));
    const io::IntegerRange level_range{1, kMaxGridPoints};
    long long total = 1;
    for (const UncertainInput& in : inputs) {
      int n = 1;
      if (in.distribution.kind != DistributionKind::kFixed) {
        if (levels.is_number()) n = d.integer("levels", level_range);
        else if (levels.contains(in.label)) n = per_input->integer(in.label, level_range);
        else d.fail("levels", "names no levels of '" + in.label + "': " + grid_levels_form(inputs, levels));
        if (n > 1 && (!std::isfinite(in.distribution.support_lower()) || !std::isfinite(in.distribution.support_upper())))
          d.fail("type", "a grid needs bounded distributions (uniform, log_uniform); '" + in.label + "' is " +
                             in.distribution.describe());
      }
      spec.grid_levels.push_back(n);
      total *= n;
      if (total > kMaxGridPoints)
        d.fail("levels", "the grid would have more than " + std::to_string(kMaxGridPoints) + " points (" +
                             grid_points_text(spec.grid_levels) + "): give fewer levels");
    }
    if (per_input) per_input->finish();
    spec.samples = static_cast<int>(total);
  } else {
    const double n = d.number("samples");
    // Fewer than min_samples (but some) are the study's to refuse: a --samples
    // flag may replace them.
    if (!(n >= 1 && n <= 1e8 && n == std::floor(n)))
      d.fail("samples", "must be a whole number of samples from " + std::to_string(min_samples) + " to 1e8");
    spec.samples = static_cast<int>(n);
  }
  spec.seed = d.seed_or("seed", 1);
  d.finish();
  return spec;
}

}  // namespace

std::string sobol_balance_warning(std::uint64_t n, const std::string& points) {
  if (n == 0 || std::has_single_bit(n)) return "";
  return "design: " + std::to_string(n) + " Sobol' " + points + " are not a power of two; the sequence is "
         "balanced at 2^k points (" + std::to_string(std::bit_floor(n)) + " or " + std::to_string(std::bit_ceil(n)) +
         "), where its error is smallest";
}

std::vector<std::string> design_warnings(const StudySpec& spec) {
  std::vector<std::string> warnings = spec.warnings;
  const auto n = static_cast<std::uint64_t>(spec.design.samples);
  if (spec.design.type == DesignType::kSobol)
    if (std::string w = sobol_balance_warning(n, "points"); !w.empty()) warnings.push_back(std::move(w));
  if (spec.design.type == DesignType::kGrid)
    for (std::size_t j = 0; j < spec.inputs.size() && j < spec.design.grid_levels.size(); ++j)
      if (const UncertainInput& in = spec.inputs[j];
          spec.design.grid_levels[j] == 1 && in.distribution.kind != DistributionKind::kFixed)
        warnings.push_back("design: a grid of 1 level holds '" + in.label + "' (" + in.distribution.describe() +
                           ") at its median " + number_text(in.distribution.quantile(0.5)) +
                           " in every run: it does not vary; give it 2 or more levels, or make it fixed");
  return warnings;
}

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string extend_fingerprint(const std::string& fingerprint, const std::string& text) {
  return io::extend_key_digest(fingerprint, text);
}

std::string with_setting(const std::string& fingerprint, const std::string& flag, const std::string& value,
                         bool from_flag, const std::string& origin) {
  return io::add_run_setting(fingerprint, {flag, value, from_flag, origin});
}

std::string study_file_run_text(const io::Json& study) {
  io::Json runs = study;
  for (const char* key : kAnalysisOnlyKeys) runs.erase(key);
  return runs.dump();
}

void refuse_integrator_the_scenario_refuses(const io::JsonReader& r, const std::string& field,
                                            const Scenario& scenario, const IntegratorSettings& integrator) {
  Scenario with = scenario;
  with.integrator = integrator;
  if (std::string why; !scenario_is_valid(with, &why))
    r.fail(field, why + " (the scenario's duration " + number_text(scenario.duration_s) + " s, output rate " +
                      number_text(scenario.output_rate_hz) + " Hz)");
}

std::optional<IntegratorSettings> study_integrator(const io::JsonReader& r, const Scenario& scenario,
                                                   std::string* choice) {
  if (r.has("integrator") && r.has("accuracy"))
    r.fail("accuracy", "give either \"accuracy\" or \"integrator\", not both");
  if (r.has("integrator")) {
    // A block that names its method replaces the scenario's integrator: that
    // method's defaults for whatever the block leaves out. One without a
    // method adjusts the scenario's.
    const io::JsonReader block = r.child("integrator");
    IntegratorSettings start = scenario.integrator;
    if (block.has("method")) {
      try {
        start = default_integrator_settings(integrator_from_name(block.string("method")));
      } catch (const std::invalid_argument&) {  // named with its field by the parse below
      }
    }
    const IntegratorSettings settings = io::parse_integrator_settings(block, start);
    refuse_integrator_the_scenario_refuses(r, "integrator", scenario, settings);
    return settings;
  }
  if (!r.has("accuracy")) return std::nullopt;
  try {
    const IntegratorChoice chosen = integrator_for_accuracy(r.number("accuracy"));
    if (choice != nullptr) *choice = chosen.description;
    refuse_integrator_the_scenario_refuses(r, "accuracy", scenario, chosen.settings);
    return chosen.settings;
  } catch (const std::invalid_argument& e) {
    r.fail("accuracy", e.what());
  }
  return std::nullopt;
}

std::string with_study_identity(const std::string& fingerprint, const StudyIdentity& identity) {
  return io::add_run_setting(fingerprint, {"study", identity.type + " '" + identity.name + "'"});
}

StudyIdentity parse_study_identity(const io::JsonReader& r, const std::vector<std::string>& types) {
  io::refuse_other_config_kind(r.raw_object(), r.file(), io::ConfigKind::kStudy);
  StudyIdentity id;
  id.path = r.file();
  id.type = r.string("type");
  if (std::find(types.begin(), types.end(), id.type) == types.end())
    r.fail("type", "this command runs studies of type " + comma_separated(types));
  id.name = r.string("name");
  if (!io::is_plain_file_name(id.name))
    r.fail("name", "must be a plain file name, with no '/', '\\' or control character (results go to results/<name>.h5)");
  id.description = r.string_or("description", "");
  return id;
}

StudySpec parse_study_spec(const io::JsonReader& r, const std::vector<std::string>& types,
                           DesignKey design_key, int min_samples) {
  StudySpec s;
  const StudyIdentity identity = parse_study_identity(r, types);
  s.path = identity.path;
  s.type = identity.type;
  s.name = identity.name;
  s.description = identity.description;
  std::string fingerprint_text = study_file_run_text(r.raw_object());
  if (r.has("scenario") == r.has("model"))
    r.fail("scenario", "give exactly one of \"scenario\" (the rover) and \"model\" (an analytic test model)");
  std::vector<QoiSpec> qois;
  if (r.has("model")) {
    std::shared_ptr<AnalyticStudyModel> m;
    try {
      m = std::make_shared<AnalyticStudyModel>(r.string("model"));
    } catch (const std::invalid_argument& e) {
      r.fail("model", e.what());
    }
    s.inputs = analytic_inputs(r, *m);
    // An analytic model has one output, y: "qoi" may name it, nothing else.
    if (r.has("qoi") && r.raw("qoi") != io::Json::array({"y"}))
      r.fail("qoi", "the analytic model '" + r.string("model") + "' has one output, y, which the study analyses: "
                    "leave \"qoi\" out (or give [\"y\"]); the rover's QoIs need a \"scenario\"");
    s.model = m;
  } else {
    const std::string scenario = io::resolve_relative(s.path, r.string("scenario"));
    io::ScenarioSources sources;
    Scenario nominal_scenario;
    try {
      sources = io::read_scenario_sources(scenario);
      nominal_scenario = io::build_scenario(sources).scenario;
    } catch (const io::ConfigError& e) {
      r.fail("scenario", e.what());
    }
    const double duration_s = nominal_scenario.duration_s, output_rate_hz = nominal_scenario.output_rate_hz;
    const std::optional<IntegratorSettings> integrator = study_integrator(r, nominal_scenario, &s.accuracy_choice);
    qois = parse_qois(r, s.path);
    refuse_references_beside_the_run(r, qois, scenario, duration_s);
    if (std::string coarse = coarse_recording_warning(qois, output_rate_hz); !coarse.empty())
      s.warnings.push_back(std::move(coarse));
    const std::vector<Channel> channels = parse_channels(r);
    if (r.has("parameters")) s.inputs = parse_rover_parameters_block(r, sources);
    std::vector<std::string> names;
    for (const UncertainInput& in : s.inputs) names.push_back(in.name);
    fingerprint_text += file_text(scenario) + file_text(sources.rover_path) + file_text(sources.terrain_path);
    s.files.add(scenario, "'scenario' in " + s.path);
    s.files.add_all(sources.files);
    for (std::size_t k = 0; k < qois.size(); ++k)
      if (qois[k].reference) {
        fingerprint_text += file_text(qois[k].reference->path);
        s.files.add(qois[k].reference->path, "'qoi[" + std::to_string(k) + "].reference' in " + s.path);
      }
    auto rover = std::make_shared<RoverStudyModel>(std::move(sources), names, qois, channels, integrator);
    refuse_a_refused_base_point(r, *rover, s.inputs);
    refuse_inputs_that_cannot_vary_alone(r, *rover, s.inputs);
    refuse_supports_the_model_refuses(r, *rover, s.inputs);
    warn_of_refused_tails(*rover, s.inputs, s);
    s.rover = rover;
    s.model = rover;
  }
  warn_of_far_truncations(s.inputs, s);
  refuse_nothing_varied(r, s.inputs);
  if (design_key == DesignKey::kByCaller) {
    // the caller reads "design"
  } else if (r.has("design")) {
    s.design = parse_design(r.child("design"), s.inputs, min_samples);
  } else {
    r.fail("design", "missing: {\"type\": \"monte_carlo\" | \"latin_hypercube\" | \"sobol\" | \"grid\", "
                     "\"samples\": N, \"seed\": S}");
  }
  s.fingerprint = with_study_identity(io::config_fingerprint(fingerprint_text), identity);
  return s;
}

DesignMatrix study_design(const StudySpec& spec) {
  const auto d = static_cast<Eigen::Index>(spec.inputs.size());
  const auto n = static_cast<Eigen::Index>(spec.design.samples);
  std::vector<int> varied;
  for (std::size_t i = 0; i < spec.inputs.size(); ++i)
    if (spec.inputs[i].distribution.kind != DistributionKind::kFixed) varied.push_back(static_cast<int>(i));
  DesignMatrix x(n, d);
  for (Eigen::Index j = 0; j < d; ++j) x.col(j).setConstant(spec.inputs[static_cast<std::size_t>(j)].distribution.a);
  if (varied.empty()) return x;
  DesignMatrix unit;
  if (spec.design.type == DesignType::kGrid) {
    std::vector<int> levels;
    for (int i : varied) levels.push_back(spec.design.grid_levels[static_cast<std::size_t>(i)]);
    unit = unit_grid(levels);
  } else {
    // A signal stops a long draw (10^7 points take seconds): WorkStopped, as for a run.
    unit = unit_design(spec.design.type, spec.design.samples, static_cast<int>(varied.size()), spec.design.seed,
                       &InterruptGuard::flag());
  }
  for (std::size_t k = 0; k < varied.size(); ++k) {
    const Distribution& dist = spec.inputs[static_cast<std::size_t>(varied[k])].distribution;
    for (Eigen::Index row = 0; row < n; ++row) {
      if (row % kRowsBetweenStopChecks == 0) stop_if_requested(&InterruptGuard::flag(), "mapping the design");
      x(row, varied[k]) = dist.quantile(unit(row, static_cast<Eigen::Index>(k)));
    }
  }
  return x;
}

std::vector<std::string> input_labels(const StudySpec& spec) {
  std::vector<std::string> labels;
  for (const UncertainInput& in : spec.inputs) labels.push_back(in.label);
  return labels;
}

namespace {

std::string reference_missed_warning(const QoiSpec& qoi, const std::vector<double>& values) {
  const double span = value_span(qoi.reference->value);
  if (!every_rms_exceeds_span(values, span)) return "";
  return qoi.name + ": " + reference_missed_text("every run misses", qoi.reference->path, span, qoi_unit(qoi),
                                                 "channel named");
}

// How many of `values` are finite (runs that did not fail), and how many of
// those `matches`.
struct FiniteCount {
  long long finite = 0, matching = 0;
};
template <class Predicate>
FiniteCount count_finite_values(const std::vector<double>& values, Predicate matches) {
  FiniteCount count;
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    ++count.finite;
    if (matches(v)) ++count.matching;
  }
  return count;
}

// Runs whose lowest B_l z is at their end (t_min the run's end, deflection
// 0): the rover was still falling, no compression to describe.
std::string still_falling_warning(const RoverStudyModel& model, const QoiSpec& qoi, const std::vector<double>& values) {
  const double end_s = model.nominal().scenario.duration_s;
  const auto [finite, falling] = count_finite_values(values, [&](double v) {
    return qoi.kind == QoiKind::kTMin ? v >= end_s * (1.0 - kRunEndTolerance) : v == 0.0;
  });
  if (falling == 0) return "";
  return qoi.name + ": " + std::to_string(falling) + " of " + std::to_string(finite) +
         " runs reach their lowest B_l z at the run's end (still falling: did a wheel touch the ground?); their " +
         qoi.name + " describes no compression: lengthen \"duration\" or check the drop height";
}

std::string unsettled_warning(const RoverStudyModel& model, const QoiSpec& qoi, const std::vector<double>& values) {
  const double end_s = model.nominal().scenario.duration_s;
  const auto [finite, at_end] =
      count_finite_values(values, [&](double v) { return !settled_before_end(v, end_s); });
  if (at_end == 0) return "";
  return qoi.name + ": " + std::to_string(at_end) + " of " + std::to_string(finite) +
         " runs had not settled within the run's " + number_text(end_s) + " s (B_l z stayed within the " +
         number_text(qoi.settling_band) + " m band around its last value for less than the last " +
         number_text(100.0 * kMinSettledShare) + " % of the run): their value is not a settling time; "
         "lengthen \"duration\" or widen \"band\"";
}

}  // namespace

std::string qoi_values_warning(const RoverStudyModel& model, std::size_t q, const std::vector<double>& values) {
  if (q >= model.qois().size()) return "";
  const QoiSpec& qoi = model.qois()[q];
  if (qoi.kind == QoiKind::kSettlingTime) return unsettled_warning(model, qoi, values);
  if (qoi.kind == QoiKind::kTMin || qoi.kind == QoiKind::kDeflection) return still_falling_warning(model, qoi, values);
  if (qoi.kind == QoiKind::kRmsVs && qoi.reference && !qoi.reference->value.empty())
    return reference_missed_warning(qoi, values);
  return "";
}

std::string qoi_values_warning(const StudySpec& spec, std::size_t q, const std::vector<double>& values) {
  return spec.rover ? qoi_values_warning(*spec.rover, q, values) : "";
}

}  // namespace rover::study
