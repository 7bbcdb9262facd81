// See calibration.hpp.
#include "study/studies/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_real_distribution.hpp>
#include <Eigen/Core>
#include <nlopt.hpp>

#include "core/metrics.hpp"
#include "core/simulate.hpp"
#include "io/checkpoint.hpp"
#include "io/csv.hpp"
#include "io/hdf5_file.hpp"
#include "io/plot.hpp"
#include "study/studies/calibration_mcmc.hpp"
#include "study/runtime/calibration_mpi.hpp"
#include "study/studies/calibration_fit.hpp"
#include "study/studies/calibration_probe.hpp"
#include "study/model/distribution_json.hpp"
#include "study/estimators/least_squares_uncertainty.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::study {
namespace {

std::string format_number(double v, int digits = 4) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
  return buffer;
}

constexpr const char* kTimeOffset = "time_offset";
// A measured curve whose heights span less than this is constant.
constexpr double kConstantCurveRange_m = 1e-9;
// Data may end this share of the duration past the simulated end (rounding of
// sample times).
constexpr double kSpanTolerance = 1e-9;
constexpr const char* kLeastSquaresAlgorithm = "levenberg_marquardt";
// The integration check tightens the tolerances by this factor, or by its
// square when the shift exceeds kFarShiftFactor times the limit.
constexpr double kTighteningFactor = 10.0;
constexpr double kFarShiftFactor = 10.0;
// The reference integrator of the integration check: Dormand-Prince at the
// tightest tolerances that run through every contact event of the drops.
constexpr double kReferenceRelativeTolerance = 1e-8;
constexpr double kReferenceAbsoluteTolerance = 1e-11;

IntegratorSettings reference_integrator() {
  IntegratorSettings settings = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  settings.relative_tolerance = kReferenceRelativeTolerance;
  settings.absolute_tolerance = kReferenceAbsoluteTolerance;
  return settings;
}

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

// The canonical name of a fitted parameter; an unknown one is refused with
// the nearest names, blamed on --fit or on the study's "fit".
std::string canonical_fit_name(const io::JsonReader& r, const CalibrationOverrides& o,
                               const ParameterSpace& space, const std::string& name) {
  if (name == kTimeOffset) return "";
  try {
    return space.canonical(name);
  } catch (const std::invalid_argument& e) {
    if (!o.fit.empty()) throw io::ConfigError(std::string("--fit: ") + e.what());
    r.fail("fit", e.what());
  }
  return "";
}

void read_fit_parameters(const io::JsonReader& r, const CalibrationOverrides& o, const ParameterSpace& space,
                         CalibrationStudy& s) {
  const io::JsonReader bounds = r.child("bounds");
  const io::JsonReader initial = r.child("initial");
  const io::Json no_scales = io::Json::object();
  const io::JsonReader log_scale = r.has("log_scale") ? r.child("log_scale") : io::JsonReader(no_scales, s.common.path);
  for (const std::string& name : fit_names(r, o)) {
    FitParameter p;
    p.name = name;
    p.canonical = canonical_fit_name(r, o, space, name);
    for (const auto& q : s.fit)
      if (q.name == name || (!p.canonical.empty() && q.canonical == p.canonical))
        r.fail("fit", "parameter '" + name + "' is listed twice");
    if (name == kTimeOffset && s.datasets.size() > 1)
      r.fail("fit", "time_offset can be fitted for one curve only; with several each curve's offset is profiled");
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
    p.initial = initial.has(name) ? initial.number(name)
                                  : (p.canonical.empty() ? 0.0 : space.nominal(p.canonical));
    if (!(p.initial >= p.lower && p.initial <= p.upper))
      initial.fail(name, "initial value " + format_number(p.initial, 6) + " outside the bounds [" +
                             format_number(p.lower, 6) + ", " + format_number(p.upper, 6) + "]");
    p.prior = p.log_scale ? log_uniform(p.lower, p.upper) : uniform(p.lower, p.upper);
    s.fit.push_back(p);
  }
  if (r.has("log_scale")) log_scale.finish();
  (void)bounds;
  (void)initial;
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
  double offset_upper = s.offset_max_s;
  for (const FitParameter& f : s.fit)
    if (f.name == kTimeOffset) offset_upper = f.upper;
  if (d.t.back() - offset_upper > duration_s * (1.0 + kSpanTolerance))
    throw io::ConfigError(d.path + ": the data run to t = " + format_number(d.t.back(), 6) +
                          " s, past the end of the simulated " + format_number(duration_s, 6) + " s of " +
                          d.scenario_path + " even at the largest time offset, " + format_number(offset_upper, 6) +
                          " s (field 'bounds.time_offset'); lengthen the scenario's \"duration\" or cut the data");
}

// Bounds and initial values of parameters not fitted are accepted (a study
// file may list several so that --fit can choose), but each must name a
// parameter; the offset range is always used.
void bounds_of_unfitted_parameters(const io::JsonReader& r, const ParameterSpace& space, CalibrationStudy& s) {
  const io::JsonReader bounds = r.child("bounds");
  const io::JsonReader initial = r.child("initial");
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

// One evaluation of the objective: per dataset the offset, the pooled RMS,
// and the objective NLopt minimises (the RMS for one curve; for several,
// sum_k n_k log RMS_k / N, the profile likelihood with a noise sd per curve).
struct Evaluation {
  std::vector<double> offsets;
  double rms = 0.0, objective = 0.0;
  int status = 0;
};

Evaluation evaluate(const CalibrationStudy& s, const std::vector<double>& values) {
  const CalibrationResiduals r = calibration_residuals(s, values);
  Evaluation e;
  e.offsets.assign(s.datasets.size(), 0.0);
  if (!r.ok) {
    e.status = 1;
    e.rms = 1.0;  // a failed run is a very bad fit, not the end of the calibration
    e.objective = s.datasets.size() == 1 ? e.rms : 1e3;
    return e;
  }
  e.offsets = r.offsets;
  double rss = 0.0, log_sum = 0.0;
  std::size_t n = 0;
  for (const auto& residuals : r.residuals) {
    double rss_k = 0.0;
    for (double v : residuals) rss_k += v * v;
    rss += rss_k;
    n += residuals.size();
    log_sum += 0.5 * static_cast<double>(residuals.size()) *
               std::log(std::max(rss_k / static_cast<double>(residuals.size()), 1e-300));
  }
  e.rms = std::sqrt(rss / static_cast<double>(n));
  e.objective = s.datasets.size() == 1 ? e.rms : log_sum / static_cast<double>(n);
  return e;
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

std::vector<double> shifted_residuals(const std::vector<double>& t, const std::vector<double>& z,
                                      const std::vector<double>& t_d, const std::vector<double>& z_d,
                                      double offset) {
  std::vector<double> r(t_d.size());
  for (std::size_t i = 0; i < t_d.size(); ++i) r[i] = interpolate(t, z, t_d[i] - offset) - z_d[i];
  return r;
}

double shifted_rms(const std::vector<double>& t, const std::vector<double>& z,
                   const std::vector<double>& t_d, const std::vector<double>& z_d, double offset) {
  double sum = 0.0;
  for (std::size_t i = 0; i < t_d.size(); ++i) {
    const double d = interpolate(t, z, t_d[i] - offset) - z_d[i];
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(t_d.size()));
}

double best_offset(const std::vector<double>& t, const std::vector<double>& z,
                   const std::vector<double>& t_d, const std::vector<double>& z_d, double lo,
                   double hi) {
  const int n = std::max(2, static_cast<int>(std::ceil((hi - lo) / 1e-3)));
  double best = lo, best_rms = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= n; ++i) {
    const double o = lo + (hi - lo) * i / n;
    const double r = shifted_rms(t, z, t_d, z_d, o);
    if (r < best_rms) {
      best_rms = r;
      best = o;
    }
  }
  // Golden-section polish within one scan step either side.
  double a = std::max(lo, best - (hi - lo) / n), b = std::min(hi, best + (hi - lo) / n);
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = shifted_rms(t, z, t_d, z_d, c), fd = shifted_rms(t, z, t_d, z_d, d);
  while (b - a > 1e-7) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = shifted_rms(t, z, t_d, z_d, c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = shifted_rms(t, z, t_d, z_d, d);
    }
  }
  const double polished = 0.5 * (a + b);
  return shifted_rms(t, z, t_d, z_d, polished) <= best_rms ? polished : best;
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

CalibrationCurve simulate_calibration_curve(const CalibrationStudy& s, std::size_t dataset,
                                            const std::vector<double>& values) {
  const CalibrationDataset& d = s.datasets.at(dataset);
  CalibrationCurve curve;
  RunRecord failure;
  const std::vector<double> inputs = s.simulated_values(values);
  const std::optional<Trajectory> tr = d.model->simulate_at(inputs.data(), &failure);
  if (!tr) {
    curve.message = failure.message;
  } else if (!tr->ok() || tr->t.size() < 2) {
    curve.message = "simulation failed (" + std::string(status_name(tr->status)) + "): " + tr->message;
  } else {
    curve.ok = true;
    curve.t_s = tr->t;
    curve.z_m = channel_values(*tr, calibration_channel(d.channel).channel);
  }
  return curve;
}

double offset_for(const CalibrationStudy& s, std::size_t dataset, const CalibrationCurve& curve,
                  const std::vector<double>& values) {
  for (std::size_t k = 0; k < s.fit.size(); ++k)
    if (s.fit[k].name == "time_offset") return values[k];
  const CalibrationDataset& d = s.datasets.at(dataset);
  return best_offset(curve.t_s, curve.z_m, d.t, d.z, s.offset_min_s, s.offset_max_s);
}

CalibrationResiduals calibration_residuals(const CalibrationStudy& s, const std::vector<double>& values) {
  CalibrationResiduals out;
  for (std::size_t k = 0; k < s.datasets.size(); ++k) {
    const CalibrationCurve curve = simulate_calibration_curve(s, k, values);
    if (!curve.ok) {
      out.message = curve.message;
      return out;
    }
    const CalibrationDataset& d = s.datasets[k];
    out.offsets.push_back(offset_for(s, k, curve, values));
    out.residuals.push_back(shifted_residuals(curve.t_s, curve.z_m, d.t, d.z, out.offsets.back()));
  }
  out.ok = true;
  return out;
}

CalibrationStudy load_calibration_study(const std::string& path, const CalibrationOverrides& o) {
  const io::Json json = io::read_json_file(path);
  const io::JsonReader r(json, path);
  CalibrationStudy s;
  s.common = parse_study_common(r, "calibration");
  s.integrator = r.has("integrator") || r.has("accuracy") ? s.common.setup.scenario.integrator
                                     : default_integrator_settings(IntegratorMethod::kRosenbrockW);
  s.integration_check.reference = reference_integrator();
  if (o.data_path.empty() && !r.has("data")) r.fail("data", "missing: give the measured curve here or with --data");
  const std::string study_scenario = io::resolve_relative(path, r.string("scenario"));
  auto add_dataset = [&](const std::string& file, const std::string& scenario, const std::string& channel) {
    CalibrationDataset d;
    d.path = file;
    d.scenario_path = scenario;
    d.channel = channel;
    d.sources = io::read_scenario_sources(scenario);
    (void)io::build_scenario(d.sources);  // the scenario's own checks, before any run
    // The checks `rover compare` makes (monotonic times, >= 3 rows, sane values).
    const io::MeasuredCurve curve = io::read_measured_curve(file);
    d.t = curve.t_s;
    d.z = curve.z_m;
    s.data_path += (s.data_path.empty() ? "" : ", ") + file;
    s.datasets.push_back(std::move(d));
  };
  if (!o.data_path.empty()) {
    (void)r.has("data");  // the command line's curve replaces the study's
    add_dataset(o.data_path, study_scenario, "B_l_z");
  } else if (r.raw("data").is_string()) {
    add_dataset(io::resolve_relative(path, r.string("data")), study_scenario, "B_l_z");
  } else {
    const io::Json& list = r.raw("data");
    if (!list.is_array() || list.empty())
      r.fail("data", "expected a file name or a non-empty list of {\"file\", \"scenario\", \"channel\"}");
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!list[i].is_object()) r.fail("data", "entry " + std::to_string(i) + " is not an object");
      const io::JsonReader item(list[i], path, r.field("data") + "[" + std::to_string(i) + "]");
      const std::string file = io::resolve_relative(path, item.string("file"));
      const std::string scenario =
          item.has("scenario") ? io::resolve_relative(path, item.string("scenario")) : study_scenario;
      const std::string channel = item.string_or("channel", "B_l_z");
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
      item.finish();
    }
  }

  const std::string configured_method = r.string_or("method", "optimize");
  const std::string method = o.method.empty() ? configured_method : o.method;
  if (method == "optimize") s.method = CalibrationMethod::optimize;
  else if (method == "mcmc") s.method = CalibrationMethod::mcmc;
  else r.fail("method", "unknown method '" + method + "' (optimize or mcmc)");

  const ParameterSpace space(s.datasets.front().sources.rover, s.datasets.front().sources.scenario);
  read_fit_parameters(r, o, space, s);
  bounds_of_unfitted_parameters(r, space, s);
  build_dataset_models(s);
  for (const CalibrationDataset& d : s.datasets) check_data_fits_the_run(s, d);

  // Priors (used by the mcmc method; checked whatever the method).
  if (r.has("priors")) {
    const io::JsonReader priors = r.child("priors");
    for (FitParameter& p : s.fit) {
      if (!priors.has(p.name)) continue;
      const io::JsonReader prior = priors.child(p.name);
      const Distribution d = parse_distribution(prior, std::numeric_limits<double>::quiet_NaN());
      std::string why;
      if (!d.IsValid(&why)) priors.fail(p.name, why);
      // The prior is truncated to the bounds: it needs mass inside them.
      if (!(d.cdf(p.upper) - d.cdf(p.lower) > 0.0) && d.kind != DistributionKind::kFixed)
        priors.fail(p.name, d.describe() + " has no probability inside the bounds [" + format_number(p.lower, 6) +
                                ", " + format_number(p.upper, 6) + "]");
      prior.finish();
      p.prior = d;
    }
    priors.finish();
  }

  if (r.has("mcmc")) {
    const io::JsonReader m = r.child("mcmc");
    const std::string sampler = m.string_or("sampler", "independence");
    if (sampler == "independence") s.mcmc.sampler = McmcSampler::independence;
    else if (sampler == "ensemble") s.mcmc.sampler = McmcSampler::ensemble;
    else m.fail("sampler", "unknown sampler '" + sampler + "' (independence or ensemble)");
    s.mcmc.walkers = m.integer_or("walkers", s.mcmc.walkers);
    s.mcmc.steps = m.integer_or("steps", static_cast<int>(s.mcmc.steps));
    if (m.has("discard")) s.mcmc.discard = m.integer_or("discard", 0);
    s.mcmc.target_ess = m.has("target_ess") ? m.non_negative("target_ess") : s.mcmc.target_ess;
    s.mcmc.max_rhat = m.has("max_rhat") ? m.positive("max_rhat") : s.mcmc.max_rhat;
    if (!(s.mcmc.max_rhat > 1.0)) m.fail("max_rhat", "must be above 1, got " + format_number(s.mcmc.max_rhat, 6));
    s.mcmc.seed = m.seed_or("seed", s.mcmc.seed);
    s.mcmc.predictive_draws = m.integer_or("predictive_draws", s.mcmc.predictive_draws);
    if (m.has("noise_sd")) {
      if (m.raw("noise_sd").is_number()) {
        s.mcmc.sample_noise = false;
        s.mcmc.known_noise_sd_m = m.positive("noise_sd");
      } else {
        const io::JsonReader noise = m.child("noise_sd");
        s.mcmc.noise_prior = parse_distribution(noise, std::numeric_limits<double>::quiet_NaN());
        std::string why;
        if (!s.mcmc.noise_prior.IsValid(&why)) m.fail("noise_sd", why);
        if (!(s.mcmc.noise_prior.support_lower() >= 0))
          m.fail("noise_sd", "the noise sd prior must not extend below 0");
        noise.finish();
      }
    }
    if (s.mcmc.predictive_draws < 0) m.fail("predictive_draws", "must not be negative");
    m.finish();
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
    r.fail("mcmc.walkers", "got " + std::to_string(s.mcmc.walkers) + "; must be even and at least " +
                               std::to_string(2 * sampled) + ", twice the " + std::to_string(sampled) +
                               " sampled parameters (" + sampled_names + ")");
  if (s.mcmc.steps <= 0) r.fail("mcmc.steps", "must be positive, got " + std::to_string(s.mcmc.steps));
  const long discard = mcmc_discard(s.mcmc, s.mcmc.sampler);
  if (discard < 0 || s.mcmc.steps - discard < 4)
    r.fail("mcmc.discard", "must be >= 0 and leave at least 4 of the " + std::to_string(s.mcmc.steps) +
                               " steps, got " + std::to_string(discard));

  // Read every key even when the command line overrides it (no "unknown key").
  const std::string configured_algorithm = r.string_or("algorithm", kLeastSquaresAlgorithm);
  const int configured_evaluations = r.integer_or("max_evaluations", 40);
  const int configured_starts = r.integer_or("starts", 1);
  s.algorithm = !o.algorithm.empty() ? o.algorithm : configured_algorithm;
  if (s.algorithm != kLeastSquaresAlgorithm && static_cast<int>(nlopt_algorithm_from_string(s.algorithm.c_str())) < 0)
    r.fail("algorithm", "unknown algorithm '" + s.algorithm + "' (levenberg_marquardt, or an NLopt algorithm for a first search: "
                        "LN_BOBYQA, LN_NELDERMEAD, GN_DIRECT_L, GN_CRS2_LM, ...)");
  if (s.algorithm.rfind("LD_", 0) == 0 || s.algorithm.rfind("GD_", 0) == 0)
    r.fail("algorithm", "'" + s.algorithm + "' needs gradients, which the simulated RMS does not have; "
                        "use a derivative-free algorithm (LN_BOBYQA, LN_SBPLX, LN_NELDERMEAD, GN_DIRECT_L, ...)");
  s.max_evaluations = o.max_evaluations ? *o.max_evaluations : configured_evaluations;
  s.max_iterations = o.max_iterations ? *o.max_iterations : r.integer_or("max_iterations", 0);
  if (s.max_iterations < 0) r.fail("max_iterations", "must be positive (or 0: 10 + 5 per parameter), got " + std::to_string(s.max_iterations));
  if (s.max_evaluations <= 0) r.fail("max_evaluations", "must be positive, got " + std::to_string(s.max_evaluations));
  s.xtol_rel = r.has("xtol_rel") ? r.positive("xtol_rel") : 1e-3;
  s.starts = o.starts ? *o.starts : configured_starts;
  if (s.starts <= 0) r.fail("starts", "must be positive, got " + std::to_string(s.starts));
  s.seed = static_cast<std::uint64_t>(r.integer_or("seed", 1));
  s.profile = r.boolean_or("profile", false) || o.profile;
  s.profile_points = r.integer_or("profile_points", s.profile_points);
  if (s.profile_points < 3) r.fail("profile_points", "must be at least 3");
  r.finish();

  // Everything that changes a result: the files, the data and the options in force.
  std::ostringstream key;
  key << s.common.fingerprint << '\n';
  for (const auto& d : s.datasets)
    key << read_text(d.path) << '\n' << read_text(d.scenario_path) << '\n' << d.channel << '\n';
  key << method << '\n' << s.algorithm << ' ' << s.max_iterations << ' ' << describe_integrator(s.integrator)
      << ' ' << s.max_evaluations << ' ' << s.starts << ' ' << s.mcmc.walkers << ' ' << s.mcmc.steps << ' ' << mcmc_discard(s.mcmc, s.mcmc.sampler) << ' ' << static_cast<int>(s.mcmc.sampler) << ' ' << s.mcmc.target_ess << ' ' << s.mcmc.max_rhat << ' ' << s.profile << ' ' << s.profile_points;
  for (const auto& p : s.fit) key << ' ' << p.name;
  s.fingerprint = io::config_fingerprint(key.str());
  return s;
}

namespace {

// The Gauss-Newton uncertainty at the optimum. Parameters: the fitted ones
// (natural units) and, when it is profiled, the time offset (its derivative
// needs no simulation: the curve is shifted). Collective: the 2 p difference
// runs go through run_task_farm. `best` (values then offset) is rank 0's and
// is broadcast. Returns the uncertainty and its parameter names on rank 0.
struct GaussNewtonResult {
  bool ok = false;
  std::string message;
  std::vector<std::string> names;
  LeastSquaresUncertainty uncertainty;
  std::vector<double> noise_rms, noise_sd;  // per curve
  std::vector<double> weights;              // per curve: 1 / s_k (1 for one curve)
  Eigen::MatrixXd weighted_jacobian;
};

// The Gauss-Newton uncertainty at the optimum (values, then offsets), over
// the fitted parameters (natural units) and the profiled offsets. Collective
// (the Jacobian's runs); the result is rank 0's.
GaussNewtonResult gauss_newton_at_optimum(const CalibrationStudy& s, std::vector<double> best,
                                          const StudyRunControl& control) {
  broadcast_from_rank0(best);
  const std::size_t p = s.fit.size(), K = s.datasets.size();
  const std::vector<double> values(best.begin(), best.begin() + static_cast<std::ptrdiff_t>(p));
  const std::vector<double> offsets(best.begin() + static_cast<std::ptrdiff_t>(p), best.end());
  const CalibrationJacobian j = calibration_jacobian(s, values, offsets, control.progress_interval_s);
  GaussNewtonResult out;
  if (world_rank() != 0) return out;
  if (!j.ok) {
    out.message = j.message + ": no intervals";
    return out;
  }
  const auto n = static_cast<std::size_t>(j.residuals.size());
  const auto q = static_cast<std::size_t>(j.jacobian.cols());
  if (n <= q) {
    out.message = "only " + std::to_string(n) + " data points for " + std::to_string(q) + " parameters: no intervals";
    return out;
  }
  // Each curve's residuals weighted by 1 / s_k (its RMS at the optimum), so
  // curves of different noise levels count by their information.
  Eigen::VectorXd residuals = j.residuals;
  out.weighted_jacobian = j.jacobian;
  std::size_t row = 0;
  for (std::size_t k = 0; k < K; ++k) {
    const auto rows = static_cast<Eigen::Index>(s.datasets[k].t.size());
    const auto first = static_cast<Eigen::Index>(row);
    out.noise_rms.push_back(std::sqrt(j.residuals.segment(first, rows).squaredNorm() / static_cast<double>(rows)));
    out.weights.push_back(K == 1 || out.noise_rms[k] == 0 ? 1.0 : 1.0 / out.noise_rms[k]);
    residuals.segment(first, rows) *= out.weights[k];
    out.weighted_jacobian.middleRows(first, rows) *= out.weights[k];
    row += s.datasets[k].t.size();
  }
  Eigen::VectorXd theta(static_cast<Eigen::Index>(q));
  for (std::size_t k = 0; k < p; ++k) theta[static_cast<Eigen::Index>(k)] = values[k];
  for (const auto& f : s.fit) out.names.push_back(f.name);
  if (!s.offset_fitted())
    for (std::size_t k = 0; k < K; ++k) {
      out.names.push_back(K == 1 ? "time_offset" : "time_offset[" + std::to_string(k) + "]");
      theta[static_cast<Eigen::Index>(p + k)] = offsets[k];
    }
  out.uncertainty = gauss_newton_uncertainty(theta, residuals, out.weighted_jacobian, 0.95, out.names);
  // The noise sd of each curve: for one curve s itself; for several, each
  // curve's RMS scaled like s (by sqrt(N / (N - q)) through the weighted fit).
  for (std::size_t k = 0; k < K; ++k)
    out.noise_sd.push_back(K == 1 ? out.uncertainty.noise_sd : out.noise_rms[k] * out.uncertainty.noise_sd);
  out.ok = true;
  return out;
}

// Profile likelihood (Bates & Watts 1988, ch. 6; Venzon & Moolgavkar 1988):
// for each fitted parameter (a fitted time_offset excepted) a grid of
// `profile_points` values over +-4 Gauss-Newton standard errors around the
// optimum (the whole bounds when the se is not finite), clipped to the bounds;
// at each value the other parameters are re-optimised with BOBYQA (at most
// max_evaluations simulations) and the offsets profiled as in the fit. The
// profile is the weighted RSS sum_k RSS_k / s_k^2 (s_k: each curve's noise sd
// at the optimum), so the threshold is chi2_1(0.95) with unit variance.
// Collective: one task per grid point, fanned out with run_task_farm.
struct ParameterProfile {
  std::string name;
  std::vector<double> values, weighted_rss;
  ProfileInterval interval;
  bool complete = false;
};

std::vector<ParameterProfile> profile_parameters(const CalibrationStudy& s, const GaussNewtonResult& gn,
                                                 std::vector<double> best, const StudyRunControl& control) {
  const std::size_t p = s.fit.size(), K = s.datasets.size();
  const std::size_t G = static_cast<std::size_t>(s.profile_points);
  // Rank 0 lays out the grids and the noise sds; every rank gets them.
  std::vector<double> layout;  // best (p + K), noise sd (K), then per parameter G values
  std::vector<std::size_t> profiled;
  for (std::size_t j = 0; j < p; ++j)
    if (s.fit[j].name != "time_offset") profiled.push_back(j);
  if (world_rank() == 0) {
    layout = best;
    for (std::size_t k = 0; k < K; ++k) layout.push_back(gn.ok ? gn.noise_sd[k] : 0.0);
    for (std::size_t j : profiled) {
      const FitParameter& f = s.fit[j];
      const double se = gn.ok ? gn.uncertainty.standard_error[static_cast<Eigen::Index>(j)] : NAN;
      double lo = f.lower, hi = f.upper;
      if (std::isfinite(se) && se > 0) {
        lo = std::max(f.lower, best[j] - 4.0 * se);
        hi = std::min(f.upper, best[j] + 4.0 * se);
      }
      for (std::size_t g = 0; g < G; ++g) {
        const double u = static_cast<double>(g) / static_cast<double>(G - 1);
        layout.push_back(f.log_scale && !(std::isfinite(se) && se > 0)
                             ? std::exp(std::log(lo) + u * (std::log(hi) - std::log(lo)))
                             : lo + u * (hi - lo));
      }
    }
  }
  broadcast_from_rank0(layout);
  best.assign(layout.begin(), layout.begin() + static_cast<std::ptrdiff_t>(p + K));
  const std::vector<double> noise_sd(layout.begin() + static_cast<std::ptrdiff_t>(p + K),
                                     layout.begin() + static_cast<std::ptrdiff_t>(p + 2 * K));
  auto grid_value = [&](std::size_t i, std::size_t g) { return layout[p + 2 * K + i * G + g]; };
  if (std::any_of(noise_sd.begin(), noise_sd.end(), [](double v) { return !(v > 0); })) return {};

  auto compute = [&](int task) {
    const std::size_t i = static_cast<std::size_t>(task) / G, g = static_cast<std::size_t>(task) % G;
    const std::size_t fixed = profiled[i];
    std::vector<double> values(best.begin(), best.begin() + static_cast<std::ptrdiff_t>(p));
    values[fixed] = grid_value(i, g);
    std::vector<std::size_t> free;
    for (std::size_t k = 0; k < p; ++k)
      if (k != fixed) free.push_back(k);
    if (!free.empty()) {
      std::vector<double> x, lower, upper;
      for (std::size_t k : free) {
        x.push_back(fit_internal(s.fit[k], values[k]));
        lower.push_back(fit_internal(s.fit[k], s.fit[k].lower));
        upper.push_back(fit_internal(s.fit[k], s.fit[k].upper));
      }
      std::function<double(const std::vector<double>&)> objective = [&](const std::vector<double>& xi) {
        std::vector<double> v = values;
        for (std::size_t k = 0; k < free.size(); ++k) v[free[k]] = fit_natural(s.fit[free[k]], xi[k]);
        return evaluate(s, v).objective;
      };
      nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(free.size()));
      opt.set_lower_bounds(lower);
      opt.set_upper_bounds(upper);
      opt.set_maxeval(s.max_evaluations);
      opt.set_xtol_rel(s.xtol_rel);
      opt.set_min_objective(
          [](const std::vector<double>& xi, std::vector<double>&, void* data) {
            return (*static_cast<std::function<double(const std::vector<double>&)>*>(data))(xi);
          },
          &objective);
      double minimum = 0;
      try {
        opt.optimize(x, minimum);
      } catch (const nlopt::roundoff_limited&) {
      }
      for (std::size_t k = 0; k < free.size(); ++k) values[free[k]] = fit_natural(s.fit[free[k]], x[k]);
    }
    const CalibrationResiduals r = calibration_residuals(s, values);
    if (!r.ok) return TaskResult{task, 1, r.message, {}};
    double weighted = 0;
    for (std::size_t k = 0; k < K; ++k)
      for (double v : r.residuals[k]) weighted += v * v / (noise_sd[k] * noise_sd[k]);
    return TaskResult{task, 0, "", {weighted}};
  };
  std::vector<int> tasks(profiled.size() * G);
  for (std::size_t t = 0; t < tasks.size(); ++t) tasks[t] = static_cast<int>(t);
  TaskFarmOptions farm;
  farm.label = "calibrate: profiles";
  farm.progress_interval_s = control.progress_interval_s;
  farm.stop = &InterruptGuard::flag();
  const std::vector<TaskResult> runs = run_task_farm(tasks, compute, {}, farm);
  std::vector<ParameterProfile> profiles;
  if (world_rank() != 0) return profiles;
  for (std::size_t i = 0; i < profiled.size(); ++i) {
    ParameterProfile prof;
    prof.name = s.fit[profiled[i]].name;
    for (const TaskResult& r : runs)
      if (static_cast<std::size_t>(r.index) / G == i && r.status == 0) {
        prof.values.push_back(grid_value(i, static_cast<std::size_t>(r.index) % G));
        prof.weighted_rss.push_back(r.values.at(0));
      }
    prof.complete = prof.values.size() >= 3;
    if (prof.complete) prof.interval = profile_likelihood_interval(prof.values, prof.weighted_rss, 1.0, 0.95);
    profiles.push_back(std::move(prof));
  }
  return profiles;
}

// The evaluations of a fit, as /history stores them (one row each: the p
// parameters, K offsets, pooled rms, objective, status), with the start each
// came from.
struct FitHistory {
  std::vector<double> rows, start;
  std::vector<std::string> messages;
};

// The first search of an NLopt algorithm: one task per start (fanned out and
// checkpointed); returns the best point (values, then offsets) on rank 0.
std::vector<double> nlopt_search(const CalibrationStudy& s, const StudyRunControl& control, const std::string& out,
                                 FitHistory& fit_history) {
  const std::size_t p = s.fit.size();
  const std::size_t K = s.datasets.size();
  const std::size_t row = p + K + 3;  // parameters, offsets, rms, objective, status

  // One task = one local (or global) NLopt search from its own start point;
  // its values are the history of every evaluation, row by row.
  auto compute = [&](int start) {
    std::vector<double> x(p), lower(p), upper(p);
    boost::random::mt19937_64 engine(s.seed * 1000003ull + static_cast<std::uint64_t>(start));
    for (std::size_t k = 0; k < p; ++k) {
      const FitParameter& f = s.fit[k];
      lower[k] = fit_internal(f, f.lower);
      upper[k] = fit_internal(f, f.upper);
      x[k] = start == 0 ? fit_internal(f, f.initial)
                        : boost::random::uniform_real_distribution<double>(lower[k], upper[k])(engine);
    }
    std::vector<double> history;
    std::function<double(const std::vector<double>&)> objective = [&](const std::vector<double>& xi) {
      std::vector<double> values(p);
      for (std::size_t k = 0; k < p; ++k) values[k] = fit_natural(s.fit[k], xi[k]);
      const Evaluation e = evaluate(s, values);
      history.insert(history.end(), values.begin(), values.end());
      history.insert(history.end(), e.offsets.begin(), e.offsets.end());
      history.push_back(e.rms);
      history.push_back(e.objective);
      history.push_back(e.status);
      return e.objective;
    };
    nlopt::opt opt(s.algorithm.c_str(), static_cast<unsigned>(p));
    opt.set_lower_bounds(lower);
    opt.set_upper_bounds(upper);
    opt.set_maxeval(s.max_evaluations);
    opt.set_xtol_rel(s.xtol_rel);
    if (s.algorithm.find("MLSL") != std::string::npos || s.algorithm.find("AUGLAG") != std::string::npos) {
      nlopt::opt local(nlopt::LN_BOBYQA, static_cast<unsigned>(p));
      local.set_xtol_rel(s.xtol_rel);
      opt.set_local_optimizer(local);
    }
    nlopt::srand(s.seed + static_cast<unsigned long>(start));
    opt.set_min_objective(
        [](const std::vector<double>& xi, std::vector<double>& /*grad*/, void* data) {
          return (*static_cast<std::function<double(const std::vector<double>&)>*>(data))(xi);
        },
        &objective);
    double best = 0.0;
    TaskResult result{start, 0, "", {}};
    try {
      const nlopt::result code = opt.optimize(x, best);
      result.message = nlopt_result_to_string(static_cast<nlopt_result>(code));
    } catch (const nlopt::roundoff_limited&) {
      result.message = "ROUNDOFF_LIMITED";
    } catch (const std::exception& e) {
      if (history.empty()) throw;
      result.message = std::string("FAILURE: ") + e.what();
    }
    result.values = std::move(history);
    return result;
  };
  StudyRunOptions options{.results_path = out, .fingerprint = s.fingerprint, .resume = control.resume,
                          .label = "calibrate", .progress_interval_s = control.progress_interval_s,
                          .resume_command = control.resume_command, .checkpoint = control.checkpoint};
  const std::vector<TaskResult> results = run_study_tasks(s.starts, compute, options);

  // Every evaluation of every start, and the best of them (rank 0).
  std::vector<double>& history = fit_history.rows;
  std::vector<double>& history_start = fit_history.start;
  std::vector<std::string>& messages = fit_history.messages;
  std::size_t best_row = 0;
  double best_objective = std::numeric_limits<double>::infinity(), best_rms = best_objective;
  std::string best_status;
  for (const TaskResult& r : results) {
    messages.push_back("start " + std::to_string(r.index) + ": " + s.algorithm + " " + r.message);
    for (std::size_t k = 0; k + row <= r.values.size(); k += row) {
      const std::size_t e = history.size() / row;
      history.insert(history.end(), r.values.begin() + static_cast<std::ptrdiff_t>(k),
                     r.values.begin() + static_cast<std::ptrdiff_t>(k + row));
      history_start.push_back(r.index);
      if (r.values[k + p + K + 2] == 0 && r.values[k + p + K + 1] < best_objective) {
        best_objective = r.values[k + p + K + 1];
        best_rms = r.values[k + p + K];
        best_row = e;
        best_status = r.message;
      }
    }
  }
  if (world_rank() == 0 && !std::isfinite(best_rms))
    throw std::runtime_error("calibrate: no evaluation succeeded");
  std::vector<double> best;  // values, then offsets
  if (world_rank() == 0)
    best.assign(history.begin() + static_cast<std::ptrdiff_t>(best_row * row),
                history.begin() + static_cast<std::ptrdiff_t>(best_row * row + p + K));
  return best;
}

// Appends the least-squares evaluations to the history (start index -1).
void append_history(const LeastSquaresCalibration& fit, FitHistory& history) {
  for (const CalibrationEvaluation& e : fit.history) {
    history.rows.insert(history.rows.end(), e.values.begin(), e.values.end());
    history.rows.insert(history.rows.end(), e.offsets.begin(), e.offsets.end());
    history.rows.insert(history.rows.end(), {e.rms_m, e.objective, static_cast<double>(e.status)});
    history.start.push_back(-1);
  }
  history.messages.push_back("least squares: " + fit.message);
}

// The fit, its intervals and the integration check, tightening the
// integrator until its error moves no parameter by more than the check
// allows. Collective; the result is rank 0's.
struct CheckedFit {
  CalibrationStudy study;  // with the integrator the fit finally used
  LeastSquaresCalibration fit;
  GaussNewtonResult gn;
  IntegrationShift shift;
  ProfileProbe probe;
  std::vector<std::string> integrator_actions;
};

// Refits from a better point the profile probe found, at most.
constexpr int kMaxProbeRestarts = 5;

bool is_reference(const CalibrationStudy& s) {
  const IntegratorSettings& r = s.integration_check.reference;
  return s.integrator.method == r.method && s.integrator.relative_tolerance <= r.relative_tolerance &&
         s.integrator.absolute_tolerance <= r.absolute_tolerance;
}

// The probe's input, rank 0's, on every rank (the probe is collective).
ProbeInput probe_input_on_every_rank(const CheckedFit& c) {
  const std::size_t p = c.study.fit.size(), K = c.study.datasets.size();
  std::vector<double> packed;  // values, covariance (column-major), weights, noise sd
  if (world_rank() == 0) {
    packed = c.fit.values;
    const Eigen::MatrixXd covariance = c.gn.uncertainty.covariance.topLeftCorner(p, p);
    packed.insert(packed.end(), covariance.data(), covariance.data() + covariance.size());
    packed.insert(packed.end(), c.gn.weights.begin(), c.gn.weights.end());
    packed.push_back(c.gn.uncertainty.noise_sd);
  }
  broadcast_from_rank0(packed);
  ProbeInput in;
  auto at = packed.begin();
  in.values.assign(at, at + static_cast<std::ptrdiff_t>(p));
  in.covariance = Eigen::Map<const Eigen::MatrixXd>(packed.data() + p, static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(p));
  at += static_cast<std::ptrdiff_t>(p + p * p);
  in.curve_weights.assign(at, at + static_cast<std::ptrdiff_t>(K));
  in.noise_sd = packed.back();
  return in;
}

// The integration check of a converged fit (rank 0): whether to refit, and
// the largest shift, for every rank.
struct ShiftVerdict {
  bool refit = false;
  double largest_se = 0.0;
};
ShiftVerdict check_integration(CheckedFit& c) {
  std::vector<double> verdict{0.0, 0.0};
  if (world_rank() == 0 && c.fit.converged && c.gn.ok && !is_reference(c.study)) {
    c.shift = integration_shift(c.study, c.fit.values, c.fit.offsets, c.gn.weights, c.gn.weighted_jacobian,
                                c.gn.uncertainty.standard_error);
    verdict[0] = !c.shift.ok || c.shift.largest_se > c.study.integration_check.max_shift_se ? 1.0 : 0.0;
    verdict[1] = c.shift.ok ? c.shift.largest_se : 0.0;
  }
  broadcast_from_rank0(verdict);
  return {verdict[0] != 0.0, verdict[1]};
}

// The integrator after `tightenings` rounds that found the shift `largest_se`.
IntegratorSettings tightened(const CalibrationStudy& s, int tightenings, double largest_se) {
  IntegratorSettings next = s.integrator;
  if (tightenings >= s.integration_check.max_tightenings || next.method == IntegratorMethod::kDormandPrince45)
    return s.integration_check.reference;
  // Tenfold, or a hundredfold when the shift is ten times the limit.
  const bool far = largest_se > kFarShiftFactor * s.integration_check.max_shift_se;
  const double factor = far ? kTighteningFactor * kTighteningFactor : kTighteningFactor;
  next.relative_tolerance /= factor;
  next.absolute_tolerance /= factor;
  return next;
}

// Whether the fit and its intervals exist on rank 0, for every rank.
bool fit_has_intervals(const CheckedFit& c) {
  std::vector<double> ok{world_rank() == 0 && c.fit.converged && c.gn.ok ? 1.0 : 0.0};
  broadcast_from_rank0(ok);
  return ok[0] != 0.0;
}

CheckedFit checked_fit(const CalibrationStudy& study, std::vector<double> start, const StudyRunControl& control,
                       FitHistory& history) {
  CheckedFit c{study, {}, {}, {}, {}, {}};
  for (int tightenings = 0, restarts = 0;;) {
    c.fit = least_squares_calibration(c.study, start, control.progress_interval_s);
    append_history(c.fit, history);
    std::vector<double> best = c.fit.values;
    best.insert(best.end(), c.fit.offsets.begin(), c.fit.offsets.end());
    c.gn = gauss_newton_at_optimum(c.study, best, control);
    std::vector<double> stop{InterruptGuard::flag().load() ? 1.0 : 0.0};  // rank 0's signal, for every rank
    broadcast_from_rank0(stop);
    if (stop[0] != 0.0) throw StudyInterrupted("interrupted during the fit; nothing was written");
    const ShiftVerdict verdict = check_integration(c);
    if (verdict.refit) {
      const IntegratorSettings next = tightened(c.study, tightenings++, verdict.largest_se);
      c.integrator_actions.push_back("the integration error moved a parameter by " +
                                     format_number(verdict.largest_se, 3) + " standard errors with " +
                                     describe_integrator(c.study.integrator) + "; refitting with " +
                                     describe_integrator(next));
      // The next fit starts where the reference's optimum is predicted to be.
      start = c.fit.values;
      for (std::size_t k = 0; k < start.size() && c.shift.ok; ++k)
        start[k] = std::clamp(start[k] + c.shift.step[k], c.study.fit[k].lower, c.study.fit[k].upper);
      broadcast_from_rank0(start);
      c.study = c.study.with_integrator(next);
      continue;
    }
    if (!fit_has_intervals(c)) return c;
    c.probe = probe_profile_directions(c.study, probe_input_on_every_rank(c), control.progress_interval_s);
    if (c.probe.better_values.empty() || restarts >= kMaxProbeRestarts) return c;
    ++restarts;
    c.integrator_actions.push_back("a point " + format_number(-c.probe.better_delta_chi2, 3) +
                                   " chi-square units below the fit lies along a profile direction; refitting "
                                   "from there");
    start = c.probe.better_values;
  }
}

CalibrationOutcome run_fit(const CalibrationStudy& s, const StudyRunControl& control) {
  const InterruptGuard guard;  // Ctrl-C and SIGTERM end the fit at its next Jacobian, with exit status 130
  const std::string out = results_path(s.common, control.results_path);
  const std::size_t p = s.fit.size();
  const std::size_t K = s.datasets.size();
  const std::size_t row = p + K + 3;  // parameters, offsets, rms, objective, status
  FitHistory fit_history;
  std::vector<double> start;
  for (const FitParameter& f : s.fit) start.push_back(f.initial);
  if (s.algorithm != kLeastSquaresAlgorithm) {
    start = nlopt_search(s, control, out, fit_history);
    start.resize(p);
    broadcast_from_rank0(start);
  }
  const CheckedFit checked = checked_fit(s, start, control, fit_history);
  const GaussNewtonResult& gn = checked.gn;
  std::vector<double> best = checked.fit.values;
  best.insert(best.end(), checked.fit.offsets.begin(), checked.fit.offsets.end());

  const CalibrationStudy& used = checked.study;
  const std::vector<ParameterProfile> profiles =
      s.profile ? profile_parameters(used, gn, best, control) : std::vector<ParameterProfile>{};
  CalibrationOutcome outcome{out, true, ""};
  if (!checked.fit.converged) {
    outcome.trusted = false;
    outcome.why = "the fit did not converge: " + checked.fit.message;
  } else if (!gn.ok) {
    outcome.trusted = false;
    outcome.why = gn.message;
  } else if (checked.shift.ok && checked.shift.largest_se > used.integration_check.max_shift_se) {
    outcome.trusted = false;
    outcome.why = "the integration error moves a parameter by " + format_number(checked.shift.largest_se, 3) +
                  " standard errors even with " + describe_integrator(used.integrator);
  } else if (!checked.probe.better_values.empty()) {
    outcome.trusted = false;
    outcome.why = "a point " + format_number(-checked.probe.better_delta_chi2, 3) +
                  " chi-square units below the fit remains after " + std::to_string(kMaxProbeRestarts) +
                  " refits from better points: the objective is too rugged for a local fit";
  } else if (!checked.probe.flat.empty()) {
    outcome.trusted = false;
    outcome.why = describe_flat_parameters(checked.probe, used);
  }
  std::vector<double> trusted{outcome.trusted ? 1.0 : 0.0};  // rank 0 holds the intervals
  broadcast_from_rank0(trusted);
  outcome.trusted = trusted[0] != 0.0;
  if (world_rank() != 0) return outcome;
  const std::vector<double>& history = fit_history.rows;
  const std::vector<double>& history_start = fit_history.start;
  std::vector<std::string> messages = fit_history.messages;
  messages.insert(messages.end(), checked.integrator_actions.begin(), checked.integrator_actions.end());

  const std::vector<double> best_values(best.begin(), best.begin() + static_cast<std::ptrdiff_t>(p));
  const std::vector<double> best_offsets(best.begin() + static_cast<std::ptrdiff_t>(p), best.end());
  // The fitted curves in data time.
  std::vector<CalibrationCurve> fits;
  for (std::size_t k = 0; k < K; ++k) {
    fits.push_back(simulate_calibration_curve(used, k, best_values));
    for (double& t : fits.back().t_s) t += best_offsets[k];
  }

  std::vector<std::string> names, columns;
  for (const auto& f : s.fit) names.push_back(f.name);
  columns = names;
  for (std::size_t k = 0; k < K; ++k)
    columns.push_back(K == 1 ? "time_offset" : "time_offset[" + std::to_string(k) + "]");
  columns.insert(columns.end(), {"rms", "objective", "status"});
  io::Hdf5Writer h5(out);
  h5.write("/history", history, history.size() / row, row);
  h5.write("/history_columns", columns);
  h5.write("/history_start", history_start);
  h5.write("/best/values", best_values);
  h5.write("/best/names", names);
  h5.write("/best/time_offset", best_offsets);
  double rss = 0;
  std::size_t points = 0;
  for (std::size_t k = 0; k < K; ++k) {
    const auto r = shifted_residuals(fits[k].t_s, fits[k].z_m, s.datasets[k].t, s.datasets[k].z, 0.0);
    for (double v : r) rss += v * v;
    points += r.size();
  }
  const double best_rms = std::sqrt(rss / static_cast<double>(points));
  h5.write("/best/rms", std::vector<double>{best_rms});
  h5.attribute("/best", "converged", static_cast<long long>(checked.fit.converged));
  h5.attribute("/best", "stop_reason", std::string(least_squares_stop_name(checked.fit.stop)));
  h5.attribute("/best", "stop_message", checked.fit.message);
  h5.attribute("/best", "intervals_valid", static_cast<long long>(outcome.trusted));
  h5.attribute("/best", "not_valid_because", outcome.why);
  h5.attribute("/best", "iterations", static_cast<long long>(checked.fit.iterations));
  h5.attribute("/best", "integrator", describe_integrator(used.integrator));
  if (checked.shift.ok) {
    h5.write("/best/integration_shift", checked.shift.shift_se);
    h5.attribute("/best/integration_shift", "meaning",
                 std::string("shift of each fitted parameter, in its standard errors, when the best curves are run "
                             "with the reference integrator (") + describe_integrator(used.integration_check.reference) + ")");
  }
  if (checked.probe.ok) {
    const Eigen::MatrixXd& d = checked.probe.delta_chi2;
    std::vector<double> row_major;
    for (Eigen::Index i = 0; i < d.rows(); ++i)
      for (Eigen::Index j = 0; j < d.cols(); ++j) row_major.push_back(d(i, j));
    h5.write("/best/probe_delta_chi2", row_major, static_cast<std::size_t>(d.rows()), static_cast<std::size_t>(d.cols()));
    h5.write("/best/probe_multiples", probe_multiples());
  }
  if (gn.ok) {
    const LeastSquaresUncertainty& u = gn.uncertainty;
    const auto q = static_cast<std::size_t>(u.covariance.rows());
    auto to_vector = [](const Eigen::MatrixXd& m) {  // row-major
      std::vector<double> v;
      for (Eigen::Index i = 0; i < m.rows(); ++i)
        for (Eigen::Index j = 0; j < m.cols(); ++j) v.push_back(m(i, j));
      return v;
    };
    h5.write("/best/names_uncertainty", gn.names);
    h5.write("/best/covariance", to_vector(u.covariance), q, q);
    h5.write("/best/correlation", to_vector(u.correlation), q, q);
    h5.write("/best/stderr", std::vector<double>(u.standard_error.begin(), u.standard_error.end()));
    h5.write("/best/lower", std::vector<double>(u.lower.begin(), u.lower.end()));
    h5.write("/best/upper", std::vector<double>(u.upper.begin(), u.upper.end()));
    h5.write("/best/noise_sd", gn.noise_sd);
    h5.attribute("/best", "degrees_of_freedom", static_cast<long long>(u.degrees_of_freedom));
    h5.attribute("/best", "jacobian_rank", static_cast<long long>(u.rank));
    h5.attribute("/best", "gn_warning", u.warning);
  } else {
    h5.attribute("/best", "gn_warning", gn.message);
  }
  for (std::size_t k = 0; k < K; ++k) {  // curve 0 at /data, /fit; curve k at /data/k, /fit/k
    const std::string suffix = k == 0 ? "" : "/" + std::to_string(k);
    h5.write("/data" + suffix + "/t", s.datasets[k].t);
    h5.write("/data" + suffix + "/z", s.datasets[k].z);
    h5.write("/fit" + suffix + "/t", fits[k].t_s);
    h5.write("/fit" + suffix + "/z", fits[k].z_m);
  }
  std::vector<std::string> channels;
  for (const auto& d : s.datasets) channels.push_back(d.channel + " of " + d.path);
  h5.write("/data/curves", channels);
  h5.write("/messages", messages);
  write_study_provenance(h5, s.common);
  h5.attribute("/", "data_file", s.data_path);
  h5.attribute("/", "method", std::string("optimize"));
  h5.attribute("/", "algorithm", s.algorithm == kLeastSquaresAlgorithm ? s.algorithm : s.algorithm + " then " + kLeastSquaresAlgorithm);
  h5.attribute("/", "max_evaluations", static_cast<long long>(s.max_evaluations));
  h5.attribute("/", "starts", static_cast<long long>(s.starts));
  h5.attribute("/", "calibration_fingerprint", s.fingerprint);
  for (const ParameterProfile& prof : profiles) {
    const std::string g = "/profile/" + prof.name;
    h5.write(g + "/values", prof.values);
    h5.write(g + "/weighted_rss", prof.weighted_rss);
    if (!prof.complete) continue;
    h5.attribute(g, "best", prof.interval.best);
    h5.attribute(g, "lower", prof.interval.lower);
    h5.attribute(g, "upper", prof.interval.upper);
    h5.attribute(g, "identifiable", static_cast<long long>(prof.interval.identifiable));
  }
  h5.commit();
  remove_checkpoint(out);
  for (const std::string& action : checked.integrator_actions) std::cerr << "calibrate: " << action << "\n";
  std::cerr << "calibrate: " << history.size() / row << " evaluations, " << checked.fit.iterations
            << " least-squares iterations; " << (checked.fit.converged ? "converged" : "NOT CONVERGED") << " ("
            << checked.fit.message << ")\n";
  if (!outcome.trusted)
    std::cerr << "calibrate: WARNING: the intervals below are NOT VALID: " << outcome.why
              << ". They are written flagged (/best intervals_valid = 0) and the exit status is 2.\n";
  std::cerr << "calibrate: best RMS " << format_number(best_rms * 1000.0) << " mm at";
  for (std::size_t k = 0; k < p; ++k) std::cerr << " " << names[k] << " = " << format_number(best_values[k], 6);
  std::cerr << ", time offset" << (K > 1 ? "s" : "");
  for (double o : best_offsets) std::cerr << " " << format_number(o, 6);
  std::cerr << " s\n";
  if (gn.ok) {
    const LeastSquaresUncertainty& u = gn.uncertainty;
    std::cerr << "calibrate: noise sd from the residuals";
    for (double sd : gn.noise_sd) std::cerr << " " << format_number(sd * 1000.0);
    std::cerr << " mm (" << u.degrees_of_freedom << " degrees of freedom); Gauss-Newton 95 % intervals"
              << (outcome.trusted ? "" : " (NOT VALID)") << ":\n";
    for (std::size_t k = 0; k < gn.names.size(); ++k) {
      const auto i = static_cast<Eigen::Index>(k);
      const double value = k < p ? best_values[k] : best_offsets[k - p];
      std::cerr << "  " << gn.names[k] << " = " << format_number(value, 6) << " +- "
                << format_number(u.upper[i] - value, 3) << " (95 %), se " << format_number(u.standard_error[i], 3)
                << (k >= p ? "  (profiled offset)" : "") << "\n";
    }
    std::cerr << "calibrate: correlation matrix (" ;
    for (std::size_t k = 0; k < gn.names.size(); ++k) std::cerr << (k ? ", " : "") << gn.names[k];
    std::cerr << "):\n";
    for (Eigen::Index i = 0; i < u.correlation.rows(); ++i) {
      std::cerr << " ";
      for (Eigen::Index j = 0; j < u.correlation.cols(); ++j) {
        char cell[32];
        std::snprintf(cell, sizeof cell, " %7.3f", u.correlation(i, j));
        std::cerr << cell;
      }
      std::cerr << "\n";
    }
    if (!u.warning.empty()) std::cerr << "calibrate: WARNING: " << u.warning << "\n";
  } else {
    std::cerr << "calibrate: WARNING: " << gn.message << "\n";
  }
  for (const ParameterProfile& prof : profiles) {
    if (!prof.complete) {
      std::cerr << "calibrate: profile of " << prof.name << ": too few successful runs\n";
    } else if (!prof.interval.identifiable) {
      std::cerr << "calibrate: profile of " << prof.name << ": NOT IDENTIFIABLE from these data (the profile stays below "
                << "the 95 % threshold over [" << format_number(prof.values.front(), 6) << ", "
                << format_number(prof.values.back(), 6) << "])\n";
    } else {
      auto end = [&](double v, bool open) { return open ? std::string(v < 0 ? "-inf" : "inf") + " (open)" : format_number(v, 6); };
      std::cerr << "calibrate: profile of " << prof.name << ": best " << format_number(prof.interval.best, 6)
                << ", 95 % profile-likelihood interval [" << end(prof.interval.lower, prof.interval.lower_open)
                << ", " << end(prof.interval.upper, prof.interval.upper_open) << "]\n";
    }
  }
  if (checked.shift.ok) {
    std::cerr << "calibrate: integration check (" << describe_integrator(used.integrator) << " against "
              << describe_integrator(used.integration_check.reference) << "): shifts";
    for (std::size_t k = 0; k < p; ++k) std::cerr << " " << names[k] << " " << format_number(checked.shift.shift_se[k], 2);
    std::cerr << " standard errors (limit " << format_number(used.integration_check.max_shift_se, 2) << ")\n";
  }
  std::cerr << "calibrate: wrote " << out << "\n";

  if (control.plot) {
    for (const ParameterProfile& prof : profiles) {
      if (prof.values.empty()) continue;
      io::LinePlot plot;
      const double minimum = *std::min_element(prof.weighted_rss.begin(), prof.weighted_rss.end());
      plot.title = s.common.name + ": profile likelihood of " + prof.name +
                   (prof.complete && !prof.interval.identifiable ? " (not identifiable from these data)" : "");
      plot.x_label = prof.name;
      plot.y_label = "(RSS - RSS_min) / s^2";
      io::Series curve, threshold;
      curve.label = "profile";
      curve.style = io::SeriesStyle::lines_points;
      curve.x = prof.values;
      for (double v : prof.weighted_rss) curve.y.push_back(v - minimum);
      threshold.label = "95 % threshold (chi2_1 = 3.84)";
      threshold.style = io::SeriesStyle::dashed;
      threshold.x = {prof.values.front(), prof.values.back()};
      threshold.y = {3.841458820694124, 3.841458820694124};
      plot.series = {curve, threshold};
      io::write_png_or_warn(plot, out.substr(0, out.size() - 3) + "_profile_" + prof.name + ".png", "calibrate",
                            std::cerr);
    }
    for (std::size_t k = 0; k < K; ++k) {
      const std::string png = out.substr(0, out.size() - 3) + (k == 0 ? "" : "_" + std::to_string(k)) + ".png";
      io::LinePlot plot;
      plot.title = s.common.name + ": data and fitted " + s.datasets[k].channel + " (RMS " +
                   format_number(gn.ok ? gn.noise_rms[k] * 1000.0 : best_rms * 1000.0) + " mm)";
      plot.x_label = "t (data clock) [s]";
      plot.y_label = s.datasets[k].channel + " [mm]";
      io::Series data, model;
      data.label = "data";
      data.x = s.datasets[k].t;
      for (double z : s.datasets[k].z) data.y.push_back(1000.0 * z);
      data.style = io::SeriesStyle::points;
      model.label = "fitted model";
      model.x = fits[k].t_s;
      for (double z : fits[k].z_m) model.y.push_back(1000.0 * z);
      plot.series = {data, model};
      io::write_png_or_warn(plot, png, "calibrate", std::cerr);
    }
  }
  return outcome;
}

}  // namespace

CalibrationEstimate estimate_calibration(const CalibrationStudy& s, const StudyRunControl& control) {
  const InterruptGuard guard;
  FitHistory history;
  std::vector<double> start;
  for (const FitParameter& f : s.fit) start.push_back(f.initial);
  const CheckedFit checked = checked_fit(s, start, control, history);
  CalibrationEstimate e{checked.study, checked.fit.values, checked.fit.offsets, false, "", {}, {}, {}, 0.0};
  std::vector<double> valid{0.0};
  if (!checked.fit.converged) {
    e.why_not = "the fit did not converge: " + checked.fit.message;
  } else if (world_rank() == 0 && !checked.gn.ok) {
    e.why_not = checked.gn.message;
  } else if (world_rank() == 0) {
    valid[0] = 1.0;
    e.names = checked.gn.names;
    e.weighted_jacobian = checked.gn.weighted_jacobian;
    e.weights = checked.gn.weights;
    e.noise_sd = checked.gn.uncertainty.noise_sd;
  }
  broadcast_from_rank0(valid);
  e.valid = valid[0] != 0.0;
  if (!e.valid && e.why_not.empty()) e.why_not = "the fit has no intervals";
  return e;
}

namespace {

// Where the posterior starts: the converged fit and its covariance, on every
// rank; nothing when the fit has no finite intervals.
McmcStart posterior_start(const CheckedFit& checked) {
  if (!fit_has_intervals(checked)) return {};
  ProbeInput fit = probe_input_on_every_rank(checked);
  if (!fit.covariance.allFinite()) return {};
  return {std::move(fit.values), std::move(fit.covariance)};
}

CalibrationOutcome run_posterior(const CalibrationStudy& s, const StudyRunControl& control) {
  const InterruptGuard guard;
  // The posterior starts at the converged fit, on the integrator its check
  // proved sufficient.
  FitHistory history;
  std::vector<double> start;
  for (const FitParameter& f : s.fit) start.push_back(f.initial);
  const CheckedFit checked = checked_fit(s, start, control, history);
  const McmcStart mcmc_start = posterior_start(checked);
  if (world_rank() == 0)
    std::cerr << "calibrate: the posterior starts "
              << (mcmc_start.values.empty() ? "at the initial values (the fit has no intervals)" : "at the converged fit")
              << ", on " << describe_integrator(checked.study.integrator) << "\n";
  const CalibrationPosterior posterior = run_calibration_mcmc(checked.study, control, mcmc_start);
  const std::string out = results_path(s.common, control.results_path);
  const CalibrationOutcome outcome{out, posterior.mixed, posterior.not_mixed_because};
  if (world_rank() != 0) return outcome;  // (also after an interrupt, which rank 0 reports)
  io::Hdf5Writer h5(out);
  write_calibration_posterior(posterior, checked.study, h5);
  write_study_provenance(h5, s.common);
  h5.commit();
  report_calibration_posterior(posterior, checked.study, std::cerr);
  std::cerr << "calibrate: wrote " << out << "\n";
  if (control.plot) plot_calibration_posterior(posterior, checked.study, out.substr(0, out.size() - 3));
  return outcome;
}

}  // namespace

std::string describe_integrator(const IntegratorSettings& i) {
  return std::string(integrator_name(i.method)) + " at rtol " + format_number(i.relative_tolerance, 3) + ", atol " +
         format_number(i.absolute_tolerance, 3);
}

CalibrationOutcome run_calibration(const CalibrationStudy& s, const StudyRunControl& control) {
  return s.method == CalibrationMethod::optimize ? run_fit(s, control) : run_posterior(s, control);
}

}  // namespace rover::study
