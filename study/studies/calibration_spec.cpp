// Reading a calibration study file (study/studies/calibration.hpp; the format
// is in docs/configuration.md): the data curves and their scenarios, the
// fitted parameters by name, bounds, scales and priors, the method and its
// options, every value checked before any run.
#include "study/studies/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <tuple>
#include <vector>
#include <sstream>
#include <stdexcept>

#include <nlopt.hpp>

#include "core/curve_overlap.hpp"
#include "core/number_text.hpp"
#include "core/simulate.hpp"
#include "io/config_kind.hpp"
#include "io/csv.hpp"
#include "io/hdf5_file.hpp"
#include "study/model/distribution_json.hpp"
#include "study/studies/measurement_noise_scale.hpp"
#include "study/studies/report_number.hpp"

namespace rover::study {
namespace {

constexpr const char* kTimeOffset = "time_offset";
// The runs' wall-time limit: a scenario key, but no property a fit could tell.
// A measured curve whose heights span less than this is constant.
constexpr double kConstantCurveRange_m = 1e-9;
// Data may end this share of the duration past the simulated end (rounding of
// sample times).
constexpr double kSpanTolerance = 1e-9;
// How far bounds.time_offset may reach past the offsets at which the data
// meet the run, at least (check_offsets_meet_the_data).
constexpr double kOffsetMargin_s = 1.0;
// The reference integrator of the integration check: Dormand-Prince at the
// tightest tolerances that run through every contact event of the drops.
constexpr double kReferenceRelativeTolerance = 1e-8;
constexpr double kReferenceAbsoluteTolerance = 1e-11;

}  // namespace

IntegratorSettings reference_integrator() {
  IntegratorSettings settings = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  settings.relative_tolerance = kReferenceRelativeTolerance;
  settings.absolute_tolerance = kReferenceAbsoluteTolerance;
  return settings;
}

namespace {

// Positive scale parameters are searched in log10 unless the study says
// otherwise: the S-joints' sharpness f and every stiffness (a key k or k_*).
bool log_scale_by_default(const std::string& canonical) {
  const std::string key = canonical.substr(canonical.rfind('.') + 1);
  return canonical == "s_structure.f" || key == "k" || key.rfind("k_", 0) == 0;
}

// Every dataset's model: its scenario, the simulated parameters, its channel
// and the study's integrator.
void build_dataset_models(CalibrationStudy& s) {
  std::vector<std::string> canonical;
  for (std::size_t k : s.simulated()) canonical.push_back(s.fit[k].canonical);
  for (CalibrationDataset& d : s.datasets)
    d.model = std::make_shared<const RoverStudyModel>(d.sources, canonical, std::vector<QoiSpec>{},
                                                      std::vector<Channel>{calibration_channel(d.channel).channel},
                                                      s.integrator);
}

// Every fitted parameter's bounds must be values the model accepts (a
// damping may not be negative, a mass not zero): each bound is set up with
// the others at their initial values, before any run, so that no fit or
// posterior proposal can reach an invalid model.
void check_bounds_are_valid_values(const io::JsonReader& r, const CalibrationStudy& s) {
  const std::vector<std::size_t> simulated = s.simulated();
  const std::vector<double> initial = s.simulated_values(s.initial_values());
  for (std::size_t c = 0; c < simulated.size(); ++c) {
    const FitParameter& f = s.fit[simulated[c]];
    for (const double bound : {f.lower, f.upper}) {
      std::vector<double> x = initial;
      x[c] = bound;
      try {
        (void)s.datasets.front().model->setup_at(x.data());
      } catch (const std::exception& e) {
        r.fail("bounds", f.name + ": the bound " + format_number(bound, 6) + " is not a valid value (" + e.what() +
                             "); give bounds inside the parameter's valid range");
      }
    }
  }
}

// The names of "fit" (or of --fit, whose errors name the flag).
std::vector<std::string> fit_names(const io::JsonReader& r, const CalibrationOverrides& o) {
  std::vector<std::string> names;
  if (!o.fit.empty()) {
    (void)r.has("fit");
    return o.fit;
  }
  const io::Json& fit = r.raw("fit");
  if (!fit.is_array() || fit.empty()) r.fail("fit", "expected a non-empty list of parameter names");
  for (const auto& n : fit) {
    if (!n.is_string()) r.fail("fit", "expected parameter names (strings)");
    names.push_back(n.get<std::string>());
  }
  return names;
}

// A problem of the fitted names, blamed on --fit when it gave them, else on
// the study's "fit".
[[noreturn]] void fail_on_fit(const io::JsonReader& r, const CalibrationOverrides& o, const std::string& problem) {
  if (!o.fit.empty()) throw io::ConfigError("--fit: " + problem);
  r.fail("fit", problem);
}

// The canonical name of a fitted parameter; an unknown one is refused with
// the nearest names, blamed on --fit or on the study's "fit".
std::string canonical_fit_name(const io::JsonReader& r, const CalibrationOverrides& o,
                               const ParameterSpace& space, const std::string& name) {
  if (name == kTimeOffset) return "";
  std::string canonical;
  try {
    canonical = space.canonical(name);
  } catch (const std::invalid_argument& e) {
    fail_on_fit(r, o, e.what());
  }
  if (const std::string why = run_setting_not_parameter(canonical); !why.empty())
    fail_on_fit(r, o, "'" + name + "' " + why + "; fit a model parameter");
  return canonical;
}

// "the default start 0 (time_offset's default)", "the default start 0.14 (the
// nominal value of the rover and scenario files)", or "initial.c_q = 0.6".
std::string describe_start(const FitParameter& p) {
  if (p.initial_given) return "the start initial." + p.name + " = " + format_number(p.initial, 6);
  return "the default start " + format_number(p.initial, 6) +
         (p.canonical.empty() ? " (time_offset's default)" : " (the nominal value of the rover and scenario files)");
}

// A start outside the bounds: blamed on "initial" when the study gave it,
// else on the bounds, which leave the default start out.
[[noreturn]] void refuse_start_outside_bounds(const io::JsonReader& bounds, const io::JsonReader& initial,
                                              const FitParameter& p) {
  const std::string range = "[" + format_number(p.lower, 6) + ", " + format_number(p.upper, 6) + "]";
  if (p.initial_given)
    initial.fail(p.name, "initial value " + format_number(p.initial, 6) + " outside bounds." + p.name + " " + range);
  bounds.fail(p.name, describe_start(p) + " is outside the bounds " + range + ": give a start inside them as "
                      "initial." + p.name + ", or bounds that hold the default");
}

void read_fit_parameters(const io::JsonReader& r, const CalibrationOverrides& o, const ParameterSpace& space,
                         CalibrationStudy& s) {
  const io::JsonReader bounds = r.child("bounds");
  const io::Json none = io::Json::object();
  const io::JsonReader initial = r.has("initial") ? r.child("initial") : io::JsonReader(none, s.identity.path);
  const io::JsonReader log_scale = r.has("log_scale") ? r.child("log_scale") : io::JsonReader(none, s.identity.path);
  for (const std::string& name : fit_names(r, o)) {
    FitParameter p;
    p.name = name;
    p.canonical = canonical_fit_name(r, o, space, name);
    for (const auto& q : s.fit) {
      if (q.name == name) fail_on_fit(r, o, "parameter '" + name + "' is listed twice");
      if (!p.canonical.empty() && q.canonical == p.canonical)
        fail_on_fit(r, o, "parameter '" + name + "' is listed twice: it and '" + q.name + "' are both " +
                              p.canonical + "; give it once");
      if (!p.canonical.empty() && !q.canonical.empty() && parameters_overlap(q.canonical, p.canonical))
        fail_on_fit(r, o, "parameters '" + q.name + "' and '" + name + "' overlap: " +
                              overlap_reason(q.canonical, p.canonical));
    }
    if (name == kTimeOffset && s.datasets.size() > 1)
      fail_on_fit(r, o, "time_offset can be fitted for one curve only; with several each curve's offset is profiled");
    const auto b = bounds.fixed_numbers<2>(name);
    p.lower = b[0];
    p.upper = b[1];
    if (!(p.lower < p.upper))
      bounds.fail(name, "bounds [" + format_number(p.lower, 6) + ", " + format_number(p.upper, 6) +
                            "] reversed or empty: lower must be below upper");
    p.log_scale = log_scale.has(name) ? log_scale.boolean(name) : log_scale_by_default(p.canonical);
    if (p.log_scale && !(p.lower > 0))
      bounds.fail(name, "a log-scale parameter needs positive bounds, got [" + format_number(p.lower, 6) + ", " +
                            format_number(p.upper, 6) + "]");
    p.initial_given = initial.has(name);
    p.initial = p.initial_given ? initial.number(name) : (p.canonical.empty() ? 0.0 : space.nominal(p.canonical));
    if (!std::isfinite(p.initial))
      r.fail("initial." + name, "missing, and the rover and scenario files set no value of '" + name +
                                    "' to start from: give one inside the bounds");
    if (!(p.initial >= p.lower && p.initial <= p.upper)) refuse_start_outside_bounds(bounds, initial, p);
    p.prior = p.log_scale ? log_uniform(p.lower, p.upper) : uniform(p.lower, p.upper);
    s.fit.push_back(p);
  }
  if (r.has("log_scale")) log_scale.finish();
  (void)bounds;
  (void)initial;
}

// Offsets at which the data overlap the run, t_data - offset in [0, duration],
// span [t_first - duration, t_last]. The offsets searched may reach beyond
// that window by its own width or kOffsetMargin_s, whichever is more: further
// out no sample meets the run, and the offset scan (1 ms steps) would take
// hours, or never end.
void check_offsets_meet_the_data(const CalibrationStudy& s, const CalibrationDataset& d, double duration_s, double lower,
                                 double upper) {
  const double window_lower = d.t.front() - duration_s, window_upper = d.t.back();
  const double margin = std::max(window_upper - window_lower, kOffsetMargin_s);
  if (lower >= window_lower - margin && upper <= window_upper + margin) return;
  throw io::ConfigError(s.identity.path + ": field 'bounds.time_offset' (value [" + format_number(lower, 6) + ", " +
                        format_number(upper, 6) + "] s): the data of " + d.path + " (t " +
                        format_number(d.t.front(), 6) + " .. " +
                        format_number(d.t.back(), 6) + " s) meet the simulated " + format_number(duration_s, 6) +
                        " s of " + d.scenario_path + " only at offsets in [" + format_number(window_lower, 6) +
                        ", " + format_number(window_upper, 6) + "] s; give bounds within [" +
                        format_number(window_lower - margin, 6) + ", " + format_number(window_upper + margin, 6) +
                        "] s");
}

// A curve the fit can use: more rows than unknowns, not constant, and
// inside the simulated span for at least the largest offset allowed.
void check_data_fits_the_run(const CalibrationStudy& s, const CalibrationDataset& d) {
  if (d.t.size() < s.fit.size() + 2)
    throw io::ConfigError(d.path + ": " + std::to_string(d.t.size()) + " rows for " + std::to_string(s.fit.size()) +
                          " fitted parameters and a time offset: need at least " + std::to_string(s.fit.size() + 2));
  const auto [low, high] = std::minmax_element(d.z.begin(), d.z.end());
  if (!(*high - *low > kConstantCurveRange_m))
    throw io::ConfigError(d.path + ": column z is constant (" + format_number(*low, 6) +
                          " m throughout): a constant curve tells nothing about the parameters");
  const double duration_s = d.model->nominal().scenario.duration_s;
  double offset_lower = s.offset_min_s, offset_upper = s.offset_max_s;
  for (const FitParameter& f : s.fit)
    if (f.name == kTimeOffset) std::tie(offset_lower, offset_upper) = std::pair(f.lower, f.upper);
  check_offsets_meet_the_data(s, d, duration_s, offset_lower, offset_upper);
  if (d.t.back() - offset_upper > duration_s * (1.0 + kSpanTolerance))
    throw io::ConfigError(d.path + ": the data run to t = " + format_number(d.t.back(), 6) +
                          " s, past the end of the simulated " + format_number(duration_s, 6) + " s of " +
                          d.scenario_path + " even at the largest time offset, " + format_number(offset_upper, 6) +
                          " s (field 'bounds.time_offset')" + milliseconds_hint(d.t.back(), duration_s + offset_upper) +
                          "; lengthen the scenario's \"duration\" or cut the data");
  if (d.t.back() - offset_lower < 0.0)
    throw io::ConfigError(d.path + ": the data end at t = " + format_number(d.t.back(), 6) +
                          " s, before the simulated run of " + d.scenario_path + " starts (t = 0) even at the "
                          "smallest time offset, " + format_number(offset_lower, 6) +
                          " s (field 'bounds.time_offset'): no sample meets the run; give the data's times from "
                          "the release, or bounds that reach them");
}

// Bounds and initial values of parameters not fitted are accepted (a study
// file may list several so that --fit can choose), but each must name a
// parameter; the offset range is always used.
void bounds_of_unfitted_parameters(const io::JsonReader& r, const ParameterSpace& space, CalibrationStudy& s) {
  const io::JsonReader bounds = r.child("bounds");
  const io::Json none = io::Json::object();
  const io::JsonReader initial = r.has("initial") ? r.child("initial") : io::JsonReader(none, r.file());
  auto check_name = [&](const io::JsonReader& where, const std::string& name) {
    if (name == kTimeOffset) return;
    try {
      (void)space.canonical(name);
    } catch (const std::invalid_argument& e) {
      where.fail(name, e.what());
    }
  };
  for (const auto& [name, value] : r.raw("bounds").items()) {
    check_name(bounds, name);
    const auto b = bounds.fixed_numbers<2>(name);
    if (!(b[0] < b[1])) bounds.fail(name, "bounds reversed or empty: lower must be below upper");
    if (name == kTimeOffset) {
      s.offset_min_s = b[0];
      s.offset_max_s = b[1];
    }
  }
  if (r.has("initial"))
    for (const auto& [name, value] : r.raw("initial").items()) {
      check_name(initial, name);
      const double v = initial.number(name);
      if (name == kTimeOffset) s.offset_initial_s = v;
    }
  bounds.finish();
  initial.finish();
}

}  // namespace

bool CalibrationStudy::offset_fitted() const {
  return std::any_of(fit.begin(), fit.end(), [](const FitParameter& p) { return p.name == "time_offset"; });
}

std::vector<std::size_t> CalibrationStudy::simulated() const {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < fit.size(); ++k)
    if (fit[k].name != kTimeOffset) out.push_back(k);
  return out;
}

std::string prior_within_bounds(const FitParameter& p) {
  const std::string prior = p.prior.describe();
  if (p.prior.support_lower() >= p.lower && p.prior.support_upper() <= p.upper) return prior;
  return prior + ", truncated to the bounds [" + format_number(p.lower, 6) + ", " + format_number(p.upper, 6) + "]";
}

std::vector<double> CalibrationStudy::initial_values() const {
  std::vector<double> values;
  for (const FitParameter& f : fit) values.push_back(f.initial);
  return values;
}

std::vector<double> CalibrationStudy::simulated_values(const std::vector<double>& values) const {
  std::vector<double> out;
  for (std::size_t k : simulated()) out.push_back(values.at(k));
  return out;
}

CalibrationStudy CalibrationStudy::with_integrator(const IntegratorSettings& settings) const {
  CalibrationStudy copy = *this;
  copy.integrator = settings;
  build_dataset_models(copy);
  return copy;
}

const std::vector<CalibrationChannel>& calibration_channels() {
  static const std::vector<CalibrationChannel> channels{
      {"B_l_z", Channel::kBlz, "world z of the left bogie pin B_l"},
      {"B_r_z", Channel::kBrz, "world z of the right bogie pin B_r"},
      {"G_z", Channel::kGz, "world z of the chassis centre of mass G"},
  };
  return channels;
}

const CalibrationChannel& calibration_channel(const std::string& name) {
  std::string valid;
  for (const CalibrationChannel& c : calibration_channels()) {
    if (c.name == name) return c;
    valid += (valid.empty() ? "" : ", ") + c.name;
  }
  throw std::invalid_argument("unknown channel '" + name + "' (valid: " + valid + ")");
}

namespace {

// A curve listed twice (by any name: a link, another spelling) would count
// its measurements twice and narrow every interval by sqrt(2).
void refuse_curve_listed_twice(const io::JsonReader& item, const std::string& file,
                               const std::vector<CalibrationDataset>& earlier) {
  for (std::size_t j = 0; j < earlier.size(); ++j) {
    std::error_code error;
    if (!std::filesystem::equivalent(file, earlier[j].path, error) || error) continue;
    item.fail("file", "the same file as data[" + std::to_string(j) + "] ('" + earlier[j].path +
                          "'): a curve listed twice counts its measurements twice and narrows every interval by "
                          "a factor sqrt(2); list each measured curve once");
  }
}

// A copy of a curve, or a near copy (a row left out, heights moved by
// rounding), counts the same measurements twice: the newest dataset is
// refused when, at half or more of its times (or of the earlier curve's, the
// shorter), an earlier curve of its channel has the same time and a height
// within kCopiedHeightTolerance_m (a copy rounded to micrometres, 6
// decimals of a metre, stays within it). Repeated measurements differ by
// their noise, tens of micrometres at the least.
constexpr double kCopiedHeightTolerance_m = 1e-6;
constexpr double kSameTimeTolerance_s = 1e-9;

struct SharedSamples {
  std::size_t times = 0;  // times the two curves share
  bool same_heights = true;  // within kCopiedHeightTolerance_m at every one
};

SharedSamples shared_samples(const CalibrationDataset& a, const CalibrationDataset& b) {
  SharedSamples shared;
  for (std::size_t i = 0, j = 0; i < a.t.size() && j < b.t.size();) {
    if (a.t[i] < b.t[j] - kSameTimeTolerance_s) {
      ++i;
    } else if (b.t[j] < a.t[i] - kSameTimeTolerance_s) {
      ++j;
    } else {
      ++shared.times;
      shared.same_heights = shared.same_heights && std::abs(a.z[i] - b.z[j]) <= kCopiedHeightTolerance_m;
      ++i;
      ++j;
    }
  }
  return shared;
}

void refuse_copied_curve(const io::JsonReader& item, const std::vector<CalibrationDataset>& datasets) {
  const CalibrationDataset& last = datasets.back();
  for (std::size_t j = 0; j + 1 < datasets.size(); ++j) {
    const CalibrationDataset& d = datasets[j];
    if (d.channel != last.channel) continue;
    const SharedSamples shared = shared_samples(d, last);
    const std::size_t shorter = std::min(d.t.size(), last.t.size());
    if (!shared.same_heights || shared.times < std::max<std::size_t>(io::kMeasuredCurveMinRows, (shorter + 1) / 2))
      continue;
    item.fail("file", "'" + last.path + "' holds the curve of data[" + std::to_string(j) + "] ('" + d.path +
                          "'): at " + std::to_string(shared.times) + " shared times (of " +
                          std::to_string(last.t.size()) + " and " + std::to_string(d.t.size()) + " rows) its " +
                          last.channel + " heights are within " + number_text(kCopiedHeightTolerance_m) +
                          " m of that curve's, far closer than repeated measurements come; a curve listed twice "
                          "counts its measurements twice and narrows every interval by a factor sqrt(2); list "
                          "each measured curve once");
  }
}

// The measured curves: "data" (a file, or a list of {file, scenario,
// channel}) or --data, each with its scenario, checked before any run.
void read_datasets(const io::JsonReader& r, const std::string& path, const CalibrationOverrides& o,
                   CalibrationStudy& s) {
  if (o.data_path.empty() && !r.has("data")) r.fail("data", "missing: give the measured curve here or with --data");
  const std::string study_scenario = io::named_input_file(r, "scenario", "a JSON file");
  auto add_dataset = [&](const std::string& file, const std::string& scenario, const std::string& channel) {
    CalibrationDataset d;
    d.path = file;
    d.scenario_path = scenario;
    d.channel = channel;
    d.sources = io::read_scenario_sources(scenario);
    (void)io::build_scenario(d.sources);  // the scenario's own checks, before any run
    // The checks `rover compare` makes (monotonic times, >= 3 rows, sane values).
    if (io::is_hdf5_file(file))
      throw io::ConfigError(file + ": an HDF5 file; a measured curve is read as CSV with columns t,z "
                                   "(docs/configuration.md)");
    const io::MeasuredCurve curve = io::read_measured_curve(file);
    if (const std::string declared = io::declared_channel(file); !declared.empty() && declared != channel)
      throw io::ConfigError(file + ": declares its z to be " + declared + " (its header), but is fitted as " +
                            channel + ": give it \"channel\": \"" + declared + "\" in 'data', or a curve of " +
                            channel);
    d.t = curve.t_s;
    d.z = curve.z_m;
    s.data_path += (s.data_path.empty() ? "" : ", ") + file;
    s.datasets.push_back(std::move(d));
  };
  if (!o.data_path.empty()) {
    (void)r.has("data");  // the command line's curve replaces the study's
    add_dataset(o.data_path, study_scenario, "B_l_z");
  } else if (r.raw("data").is_string()) {
    add_dataset(io::named_input_file(r, "data", "a CSV file"), study_scenario, "B_l_z");
  } else {
    const io::Json& list = r.raw("data");
    if (!list.is_array() || list.empty())
      r.fail("data", "expected a file name or a non-empty list of {\"file\", \"scenario\", \"channel\"}");
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!list[i].is_object()) r.fail("data", "entry " + std::to_string(i) + " is not an object");
      const io::JsonReader item(list[i], path, r.field("data") + "[" + std::to_string(i) + "]");
      const std::string file = io::named_input_file(item, "file", "a CSV file");
      const std::string scenario =
          item.has("scenario") ? io::named_input_file(item, "scenario", "a JSON file") : study_scenario;
      const std::string channel = item.string_or("channel", "B_l_z");
      refuse_curve_listed_twice(item, file, s.datasets);
      if (item.has("scenario")) {
        try {  // the scenario's own checks, named by this entry's field
          (void)io::build_scenario(io::read_scenario_sources(scenario));
        } catch (const std::exception& e) {
          item.fail("scenario", e.what());
        }
      }
      try {
        (void)calibration_channel(channel);
      } catch (const std::invalid_argument& e) {
        item.fail("channel", e.what());
      }
      try {
        add_dataset(file, scenario, channel);
      } catch (const io::ConfigError&) {
        throw;  // names the data file
      } catch (const std::exception& e) {
        item.fail("scenario", e.what());
      }
      refuse_copied_curve(item, s.datasets);
      item.finish();
    }
  }
}

CalibrationMethod read_method(const io::JsonReader& r, const CalibrationOverrides& o) {
  const std::string configured_method = r.string_or("method", "optimize");
  const std::string method = o.method.empty() ? configured_method : o.method;
  if (method == "optimize") return CalibrationMethod::optimize;
  if (method != "mcmc") r.fail("method", "unknown method '" + method + "' (optimize or mcmc)");
  return CalibrationMethod::mcmc;
}

// A prior is truncated to the bounds: it needs probability inside them, and
// its support must hold the start. The fit starts there and the chains
// around the fit; a start where the prior has no density leaves the chains
// nothing to start from.
void check_prior_holds_the_start(const io::JsonReader& priors, const FitParameter& p, const Distribution& d) {
  const std::string support =
      "its support [" + format_number(d.support_lower(), 6) + ", " + format_number(d.support_upper(), 6) + "]";
  const std::string bounds = "bounds." + p.name + " [" + format_number(p.lower, 6) + ", " +
                             format_number(p.upper, 6) + "]";
  if (!(d.cdf(p.upper) - d.cdf(p.lower) > 0.0))
    priors.fail(p.name, d.describe() + " has no probability inside " + bounds + " (" + support +
                            "): give a prior that overlaps the bounds, or bounds that reach the prior");
  if (!(p.initial >= d.support_lower() && p.initial <= d.support_upper() && std::isfinite(d.log_pdf(p.initial))))
    priors.fail(p.name, d.describe() + ": " + support + " leaves out " + describe_start(p) +
                            ", where the fit starts; give initial." + p.name + " inside the prior's support and " +
                            bounds + ", or a prior that holds the start");
}

// Priors (used by the mcmc method; checked whatever the method).
void read_priors(const io::JsonReader& r, CalibrationStudy& s) {
  if (r.has("priors")) {
    const io::JsonReader priors = r.child("priors");
    for (FitParameter& p : s.fit) {
      if (!priors.has(p.name)) continue;
      const io::JsonReader prior = priors.child(p.name);
      const Distribution d = parse_distribution(prior, std::numeric_limits<double>::quiet_NaN());
      std::string why;
      if (!d.IsValid(&why)) priors.fail(p.name, why);
      if (d.kind == DistributionKind::kFixed)
        priors.fail(p.name, d.describe() + " leaves the fitted " + p.name + " nothing to sample: to hold it at " +
                                "a value, leave it out of \"fit\" and set it in the rover or scenario file; to " +
                                "fit it, give a prior with spread (uniform, normal, ...)");
      check_prior_holds_the_start(priors, p, d);
      prior.finish();
      p.prior = d;
    }
    priors.finish();
  }
}

// The walkers a study file may give: at least 2, and at least twice the
// sampled parameters, which check_mcmc_sizes() checks once they are known.
const io::IntegerRange kWalkers{2, kMaxMcmcWalkers,
                                "that is even, from 2 to " + std::to_string(kMaxMcmcWalkers) +
                                    ", and at least twice the number of sampled parameters"};

// "mcmc": the sampler and its target, the noise model.
void read_mcmc_settings(const io::JsonReader& r, CalibrationStudy& s) {
  if (r.has("mcmc")) {
    const io::JsonReader m = r.child("mcmc");
    const std::string sampler = m.string_or("sampler", "independence");
    if (sampler == "independence") s.mcmc.sampler = McmcSampler::independence;
    else if (sampler == "ensemble") s.mcmc.sampler = McmcSampler::ensemble;
    else m.fail("sampler", "unknown sampler '" + sampler + "' (independence or ensemble)");
    s.mcmc.walkers = m.integer_or("walkers", s.mcmc.walkers, kWalkers);
    s.mcmc.steps = m.integer_or("steps", static_cast<int>(s.mcmc.steps), {1, kMaxMcmcSteps});
    if (m.has("discard")) s.mcmc.discard = m.integer("discard", {0, kMaxMcmcSteps});
    s.mcmc.target_ess = m.has("target_ess") ? m.non_negative("target_ess") : s.mcmc.target_ess;
    s.mcmc.max_rhat = m.has("max_rhat") ? m.positive("max_rhat") : s.mcmc.max_rhat;
    if (!(s.mcmc.max_rhat > 1.0)) m.fail("max_rhat", "must be above 1, got " + format_number(s.mcmc.max_rhat, 6));
    s.mcmc.seed = m.seed_or("seed", s.mcmc.seed);
    s.mcmc.predictive_draws = m.integer_or("predictive_draws", s.mcmc.predictive_draws, {0, kMaxPredictiveDraws});
    if (m.has("noise_sd")) {
      if (m.raw("noise_sd").is_number()) {
        s.mcmc.sample_noise = false;
        s.mcmc.known_noise_sd_m = m.number("noise_sd");
        if (!noise_sd_resolved(s.mcmc.known_noise_sd_m))
          m.fail("noise_sd", noise_scale_problem(s.mcmc.known_noise_sd_m));
      } else {
        const io::JsonReader noise = m.child("noise_sd");
        s.mcmc.noise_prior = parse_distribution(noise, std::numeric_limits<double>::quiet_NaN());
        std::string why;
        if (!s.mcmc.noise_prior.IsValid(&why)) m.fail("noise_sd", why);
        if (!(s.mcmc.noise_prior.support_lower() >= 0))
          m.fail("noise_sd", "the noise sd prior must not extend below 0");
        const double lower = s.mcmc.noise_prior.support_lower(), upper = s.mcmc.noise_prior.support_upper();
        if (upper > kMaxNoiseSd_m) m.fail("noise_sd", "the prior reaches " + noise_scale_problem(upper));
        if (lower < kMinNoiseSd_m)
          m.fail("noise_sd", "the prior reaches " + noise_scale_problem(lower) + "; give a support from at least " +
                                 format_number(kMinNoiseSd_m, 6) + " m (a \"min\" of 1e-12 or more)");
        noise.finish();
      }
    }
    m.finish();
  }
}

// A refused setting: blamed on `flag` when the command line gave it (it
// overrides the study file), else on the study file's `field`.
[[noreturn]] void fail_setting(const io::JsonReader& r, bool from_flag, const std::string& flag,
                               const std::string& field, const std::string& problem) {
  if (from_flag) throw io::ConfigError(flag + ": " + problem);
  r.fail(field, problem);
}

// The fewest steps the posterior's summaries keep after the burn-in.
constexpr long kMinKeptSteps = 4;

// Where the burn-in and the steps came from, for the check that leaves at least
// kMinKeptSteps steps: "--steps 2 with --discard 0", "--steps 2 (the burn-in by default 1)".
std::string discard_flags(const CalibrationOverrides& o, const McmcSettings& m, long discard) {
  if (o.discard && o.steps) return "--steps " + std::to_string(*o.steps) + " with --discard " + std::to_string(discard);
  if (o.discard) return "--discard";
  return "--steps " + std::to_string(m.steps) + " (" + (m.discard ? "'mcmc.discard' " : "the burn-in by default ") +
         std::to_string(discard) + ")";
}

// The effective sample size estimates how many independent draws the kept
// draws, walkers x (steps - burn-in), are worth: as many for independent
// draws, fewer for correlated ones (neither sampler's chains are
// anticorrelated; the estimate passes the draws only by its noise). A target
// above the kept draws is never met: the run would end NOT VALID after all
// its steps.
void refuse_unreachable_target_ess(const io::JsonReader& r, const CalibrationOverrides& o, const McmcSettings& m,
                                   long discard) {
  const long kept_steps = m.steps - discard;
  const double kept_draws = static_cast<double>(m.walkers) * static_cast<double>(kept_steps);
  if (!(m.target_ess > kept_draws)) return;
  const bool target_given = r.has("mcmc") && r.child("mcmc").has("target_ess");
  const bool from_flags = !target_given && (o.walkers || o.steps || o.discard);
  std::string flags;
  if (o.walkers) flags += "--walkers " + std::to_string(m.walkers);
  if (o.steps) flags += (flags.empty() ? "" : " ") + ("--steps " + std::to_string(m.steps));
  if (o.discard) flags += (flags.empty() ? "" : " ") + ("--discard " + std::to_string(discard));
  fail_setting(r, from_flags, flags, "mcmc.target_ess",
               std::string(target_given ? "" : "the default ") + "target_ess " + format_number(m.target_ess, 6) +
                   " can never be met: the chains keep walkers x (steps - burn-in) = " + std::to_string(m.walkers) +
                   " x (" + std::to_string(m.steps) + " - " + std::to_string(discard) + ") = " +
                   format_number(kept_draws, 12) + " draws, and their effective sample size, the number of "
                   "independent draws they are worth, is at most that; give a target_ess from 0 (exactly 'steps' "
                   "steps, no target) to " + format_number(kept_draws, 12) + ", or more walkers or steps");
}

// The posterior's sizes after the command line's overrides, checked; an
// override's error names its flag. A least-squares fit takes no overrides
// (the command refuses them as unused) and checks the file's sizes alone.
void check_mcmc_sizes(const io::JsonReader& r, CalibrationOverrides o, CalibrationStudy& s) {
  if (s.method != CalibrationMethod::mcmc) {
    o.walkers.reset();
    o.steps.reset();
    o.discard.reset();
  }
  if (o.walkers) s.mcmc.walkers = *o.walkers;
  if (o.steps) s.mcmc.steps = *o.steps;
  if (o.discard) s.mcmc.discard = *o.discard;
  std::string sampled_names;
  for (const FitParameter& p : s.fit) sampled_names += (sampled_names.empty() ? "" : ", ") + p.name;
  if (s.mcmc.sample_noise)
    for (std::size_t k = 0; k < s.datasets.size(); ++k)
      sampled_names += s.datasets.size() == 1 ? ", noise_sd" : ", noise_sd[" + std::to_string(k) + "]";
  const std::size_t sampled = s.fit.size() + (s.mcmc.sample_noise ? s.datasets.size() : 0);
  if (s.mcmc.walkers < 2 * static_cast<int>(sampled) || s.mcmc.walkers % 2 != 0)
    fail_setting(r, o.walkers.has_value(), "--walkers", "mcmc.walkers",
                 "got " + std::to_string(s.mcmc.walkers) + "; must be even and at least " + std::to_string(2 * sampled) +
                     ", twice the " + std::to_string(sampled) + " sampled parameters (" + sampled_names + ")");
  if (s.mcmc.steps <= 0) r.fail("mcmc.steps", "must be positive, got " + std::to_string(s.mcmc.steps));
  const long discard = mcmc_discard(s.mcmc, s.mcmc.sampler);
  if (discard < 0)
    fail_setting(r, o.discard.has_value(), "--discard", "mcmc.discard",
                 "the burn-in must be >= 0, got " + std::to_string(discard));
  if (s.mcmc.steps - discard < kMinKeptSteps)
    fail_setting(r, o.discard || o.steps, discard_flags(o, s.mcmc, discard),
                 s.mcmc.discard ? "mcmc.discard" : "mcmc.steps",
                 "leaves " + std::to_string(std::max(0L, s.mcmc.steps - discard)) + " step(s) after a burn-in of " +
                     std::to_string(discard) + ", and the summaries need at least " + std::to_string(kMinKeptSteps) +
                     ": give at least " + std::to_string(discard + kMinKeptSteps) + " steps" +
                     (discard > 0 ? ", or a shorter burn-in" : ""));
  refuse_unreachable_target_ess(r, o, s.mcmc, discard);
}

// The fit's options: the first-search algorithm, budgets, profile.
void read_fit_options(const io::JsonReader& r, const CalibrationOverrides& o, CalibrationStudy& s) {
  // Read every key even when the command line overrides it (no "unknown key").
  const std::string configured_algorithm = r.string_or("algorithm", kLeastSquaresAlgorithm);
  const int configured_evaluations = r.integer_or("max_evaluations", 40, {1, kMaxCalibrationEvaluations});
  const int configured_starts = r.integer_or("starts", 1, {1, kMaxCalibrationStarts});
  s.algorithm = !o.algorithm.empty() ? o.algorithm : configured_algorithm;
  const bool algorithm_flag = !o.algorithm.empty();
  if (s.algorithm != kLeastSquaresAlgorithm && static_cast<int>(nlopt_algorithm_from_string(s.algorithm.c_str())) < 0)
    fail_setting(r, algorithm_flag, "--algorithm", "algorithm",
                 "unknown algorithm '" + s.algorithm + "' (levenberg_marquardt, or an NLopt algorithm for a first search: "
                 "LN_BOBYQA, LN_NELDERMEAD, GN_DIRECT_L, GN_CRS2_LM, ...)");
  if (s.algorithm.rfind("LD_", 0) == 0 || s.algorithm.rfind("GD_", 0) == 0)
    fail_setting(r, algorithm_flag, "--algorithm", "algorithm",
                 "'" + s.algorithm + "' needs gradients, which the simulated RMS does not have; "
                 "use a derivative-free algorithm (LN_BOBYQA, LN_SBPLX, LN_NELDERMEAD, GN_DIRECT_L, ...)");
  s.max_evaluations = o.max_evaluations ? *o.max_evaluations : configured_evaluations;
  const int configured_iterations = r.integer_or(
      "max_iterations", 0,
      {0, kMaxCalibrationEvaluations,
       "from 0 (10 + 5 per parameter) to " + std::to_string(kMaxCalibrationEvaluations)});
  s.max_iterations = o.max_iterations ? *o.max_iterations : configured_iterations;
  if (s.max_iterations < 0)
    fail_setting(r, o.max_iterations.has_value(), "--max-iterations", "max_iterations",
                 "must be positive (or 0: 10 + 5 per parameter), got " + std::to_string(s.max_iterations));
  if (s.max_evaluations <= 0)
    fail_setting(r, o.max_evaluations.has_value(), "--max-evaluations", "max_evaluations",
                 "must be positive, got " + std::to_string(s.max_evaluations));
  s.xtol_rel = r.has("xtol_rel") ? r.positive("xtol_rel") : 1e-3;
  for (const char* key : {"max_evaluations", "xtol_rel"})
    if (r.has(key)) s.search_budget_keys.emplace_back(key);
  s.starts = o.starts ? *o.starts : configured_starts;
  if (s.starts <= 0)
    fail_setting(r, o.starts.has_value(), "--starts", "starts", "must be positive, got " + std::to_string(s.starts));
  if (s.starts > 1 && !o.starts && s.algorithm == kLeastSquaresAlgorithm)
    r.fail("starts", std::to_string(s.starts) + " independent starts need an NLopt first search (\"algorithm\" or "
           "--algorithm: LN_BOBYQA, GN_DIRECT_L, ...); the least-squares fit (levenberg_marquardt) starts once, "
           "at \"initial\"");
  s.seed = r.seed_or("seed", 1);
  s.profile = r.boolean_or("profile", false) || o.profile;
  s.profile_points = r.integer_or("profile_points", s.profile_points, {kMinProfilePoints, kMaxProfilePoints});
}

// The integrator of every run: the study's "integrator" (over the study
// scenario's settings) or "accuracy", else the stiff one at its defaults.
IntegratorSettings calibration_integrator(const io::JsonReader& r, CalibrationStudy& s) {
  Scenario scenario;
  try {
    scenario = io::load_scenario(io::resolve_relative(r.file(), r.string("scenario"))).scenario;
  } catch (const io::ConfigError& e) {
    r.fail("scenario", e.what());
  }
  const std::optional<IntegratorSettings> chosen = study_integrator(r, scenario, &s.accuracy_choice);
  if (chosen) return *chosen;
  const IntegratorSettings stiff = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  if (describe_integrator(scenario.integrator) != describe_integrator(stiff))
    s.integrator_origin = "the calibration's default, not the scenario's " + describe_integrator(scenario.integrator) +
                          "; the study's \"integrator\" chooses another";
  return stiff;
}

// Everything that changes a result: the files and the data (the digest), and
// the settings in force that a flag can override, each recorded with where its
// value came from, so that a --resume under another value names the flag.
std::string calibration_fingerprint(const CalibrationStudy& s, const CalibrationOverrides& o) {
  std::ostringstream key;
  key << file_text(s.identity.path) << '\n';
  for (const auto& d : s.datasets)
    key << file_text(d.path) << '\n' << file_text(d.scenario_path) << '\n' << file_text(d.sources.rover_path) << '\n'
        << file_text(d.sources.terrain_path) << '\n' << d.channel << '\n';
  key << describe_integrator(s.integrator) << ' ' << static_cast<int>(s.mcmc.sampler) << ' ' << s.mcmc.target_ess
      << ' ' << s.mcmc.max_rhat << ' ' << s.profile_points;
  std::string fit;
  for (const auto& p : s.fit) fit += (fit.empty() ? "" : ",") + p.name;
  std::string data;
  for (const auto& d : s.datasets) data += (data.empty() ? "" : ",") + d.path;
  const std::pair<std::string, std::pair<std::string, bool>> settings[] = {
      {"--data", {data, !o.data_path.empty()}},
      {"--fit", {fit, !o.fit.empty()}},
      {"--method", {s.method == CalibrationMethod::mcmc ? "mcmc" : "optimize", !o.method.empty()}},
      {"--algorithm", {s.algorithm, !o.algorithm.empty()}},
      {"--starts", {std::to_string(s.starts), o.starts.has_value()}},
      {"--max-evaluations", {std::to_string(s.max_evaluations), o.max_evaluations.has_value()}},
      {"--max-iterations", {std::to_string(s.max_iterations), o.max_iterations.has_value()}},
      {"--profile", {s.profile ? "on" : "off", o.profile}},
      {"--walkers", {std::to_string(s.mcmc.walkers), o.walkers.has_value()}},
      {"--steps", {std::to_string(s.mcmc.steps), o.steps.has_value()}},
      {"--discard", {std::to_string(mcmc_discard(s.mcmc, s.mcmc.sampler)), o.discard.has_value()}}};
  std::string fingerprint = with_study_identity(io::config_fingerprint(key.str()), s.identity);
  for (const auto& [flag, setting] : settings)
    fingerprint = with_setting(fingerprint, flag, setting.first, setting.second);
  return fingerprint;
}

}  // namespace

CalibrationStudy load_calibration_study(const std::string& path, const CalibrationOverrides& o) {
  const io::Json json = io::read_config_file(path, io::ConfigKind::kStudy);
  const io::JsonReader r(json, path);
  CalibrationStudy s;
  s.identity = parse_study_identity(r, {"calibration"});
  s.integrator = calibration_integrator(r, s);
  s.integration_check.reference = reference_integrator();
  read_datasets(r, path, o, s);
  s.method = read_method(r, o);
  const ParameterSpace space(s.datasets.front().sources.rover, s.datasets.front().sources.scenario);
  read_fit_parameters(r, o, space, s);
  bounds_of_unfitted_parameters(r, space, s);
  build_dataset_models(s);
  check_bounds_are_valid_values(r, s);
  for (const CalibrationDataset& d : s.datasets) check_data_fits_the_run(s, d);
  read_priors(r, s);
  read_mcmc_settings(r, s);
  check_mcmc_sizes(r, o, s);
  read_fit_options(r, o, s);
  r.finish();
  s.fingerprint = calibration_fingerprint(s, o);
  return s;
}

}  // namespace rover::study
