// See distribution_json.hpp.
#include "study/model/distribution_json.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <string>

#include "io/json_reader.hpp"

namespace rover::study {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A number in its shortest round-trip form, as Distribution::describe() writes it.
std::string shortest(double x) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

// The value of `key`, or the parameter's nominal value when the key is absent.
double number_or_nominal(const io::JsonReader& r, const std::string& key, double nominal) {
  if (r.has(key)) return r.number(key);
  if (std::isnan(nominal))
    r.fail(key, "missing, and the parameter has no nominal value to default to");
  return nominal;
}

// "truncate": [lower, upper], null for an open side (lower_open for a null lower).
// Returns whether the key is present.
bool parse_truncation(const io::JsonReader& r, double lower_open, Distribution& d) {
  if (!r.has("truncate")) return false;
  const io::Json& v = r.raw("truncate");
  if (!v.is_array() || v.size() != 2)
    r.fail("truncate", "expected [lower, upper] (null for an infinite side)");
  double bounds[2] = {lower_open, kInf};
  for (std::size_t i = 0; i < 2; ++i) {
    if (v[i].is_null()) continue;
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
      r.fail("truncate", "element " + std::to_string(i) + " is neither a finite number nor null");
    bounds[i] = v[i].get<double>();
  }
  if (!(bounds[0] < bounds[1]))
    r.fail("truncate", "the lower bound must be less than the upper bound");
  d.lower = bounds[0];
  d.upper = bounds[1];
  return true;
}

void reject_truncation(const io::JsonReader& r) {
  if (r.has("truncate"))
    r.fail("truncate", "applies to normal and lognormal only (bound the others with min and max)");
}

// "sd" (absolute) or "sd_percent" (of |mean|): exactly one of them, positive.
double parse_sd(const io::JsonReader& r, double mean) {
  const bool absolute = r.has("sd"), relative = r.has("sd_percent");
  if (absolute && relative) r.fail("sd_percent", "give either sd or sd_percent, not both");
  if (absolute) return r.positive("sd");
  if (!relative) r.fail("sd", "missing required field (or give sd_percent)");
  const double sd = r.positive("sd_percent") / 100.0 * std::abs(mean);
  if (!(sd > 0.0))
    r.fail("sd_percent", "is relative to |mean| = " + shortest(std::abs(mean)) +
                             ", which gives no spread; give sd instead");
  return sd;
}

}  // namespace

Distribution parse_distribution(const io::JsonReader& r, double nominal) {
  const std::string name = r.string("distribution");
  Distribution d;
  bool truncated = false;
  if (name == "fixed") {
    reject_truncation(r);
    d = fixed_value(number_or_nominal(r, "value", nominal));
  } else if (name == "uniform" || name == "log_uniform") {
    reject_truncation(r);
    const double min = r.number("min"), max = r.number("max");
    if (name == "log_uniform" && !(min > 0.0)) r.fail("min", "must be positive for log_uniform");
    if (!(min < max)) r.fail("max", "must be greater than min (" + shortest(min) + ")");
    d = name == "uniform" ? uniform(min, max) : log_uniform(min, max);
  } else if (name == "normal") {
    const double mean = number_or_nominal(r, "mean", nominal);
    d = normal(mean, parse_sd(r, mean));
    truncated = parse_truncation(r, -kInf, d);
  } else if (name == "lognormal") {
    const bool log_scale = r.has("log_mean") || r.has("log_sd");
    if (log_scale) {
      for (const char* key : {"mean", "sd", "sd_percent"})
        if (r.has(key))
          r.fail(key, "give either log_mean and log_sd, or mean and sd of X itself, not both");
      d = lognormal(r.number("log_mean"), r.positive("log_sd"));
    } else {
      const double mean = number_or_nominal(r, "mean", nominal);
      if (!(mean > 0.0))
        r.fail("mean", "the mean of a lognormal must be positive (got " + shortest(mean) + ")");
      const double sd = parse_sd(r, mean);
      // A spread the logarithm cannot hold (log_sd ~ sd / mean underflows).
      if (!(sd > kMinRelativeSpread * mean))
        r.fail(r.has("sd") ? "sd" : "sd_percent", "lognormal(mean " + shortest(mean) + ", sd " + shortest(sd) +
                                                      ") has sd not above " + shortest(kMinRelativeSpread) +
                                                      " of its mean " + shortest(mean) + spread_rule_text());
      d = lognormal_from_moments(mean, sd);
    }
    truncated = parse_truncation(r, 0.0, d);
  } else {
    r.fail("distribution",
           "unknown distribution; valid: fixed, uniform, log_uniform, normal, lognormal");
  }
  std::string why;
  if (!d.IsValid(&why)) r.fail(truncated ? "truncate" : "distribution", why);
  // The rule IsValid applied, with the parameter's configured value as a scale too.
  if (const std::string problem = negligible_spread_problem(d, nominal); !problem.empty())
    r.fail(truncated ? "truncate" : "distribution", problem);
  return d;
}

}  // namespace rover::study
