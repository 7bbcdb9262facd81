// See distributions.hpp.
#include "study/estimators/distributions.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <boost/math/constants/constants.hpp>
#include <boost/math/distributions/normal.hpp>

namespace rover::study {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The smallest truncation mass accepted: below it the normalisation (and the
// tail CDFs it is made of) would be denormal or zero.
constexpr double kMinTruncationMass = 1e-300;

// Standard normal CDF and its inverse, with the infinite ends made explicit.
double std_normal_cdf(double z) {
  if (z == -kInf) return 0.0;
  if (z == kInf) return 1.0;
  return boost::math::cdf(boost::math::normal_distribution<double>(), z);
}

double std_normal_quantile(double p) {
  if (p <= 0.0) return -kInf;
  if (p >= 1.0) return kInf;
  return boost::math::quantile(boost::math::normal_distribution<double>(), p);
}

// phi(z), 0 at the infinite ends.
double std_normal_pdf(double z) {
  if (std::isinf(z)) return 0.0;
  return std::exp(-0.5 * z * z) * boost::math::constants::one_div_root_two_pi<double>();
}

// P(lo <= Z <= hi) for Z ~ N(0, 1), lo <= hi. An interval above the mean is
// reflected below it, where the CDF is a small number held to full relative
// precision (Phi(-z) = erfc(z / sqrt 2) / 2), so no cancellation of two
// numbers close to 1.
double std_normal_mass(double lo, double hi) {
  if (lo > 0.0) return std_normal_cdf(-lo) - std_normal_cdf(-hi);
  return std_normal_cdf(hi) - std_normal_cdf(lo);
}

// N(0, 1) conditioned on [alpha, beta]. When alpha > 0 the computations run
// on the mirror image -Z, conditioned on [-beta, -alpha] (see
// std_normal_mass), and the results are mirrored back.
struct TruncatedStdNormal {
  double alpha, beta;
  bool mirrored;
  double lo, hi;          // the interval worked on (never wholly above the mean)
  double cdf_lo, cdf_hi;  // Phi(lo), Phi(hi)
  double mass;            // cdf_hi - cdf_lo

  TruncatedStdNormal(double alpha_in, double beta_in)
      : alpha(alpha_in), beta(beta_in), mirrored(alpha_in > 0.0),
        lo(mirrored ? -beta_in : alpha_in), hi(mirrored ? -alpha_in : beta_in),
        cdf_lo(std_normal_cdf(lo)), cdf_hi(std_normal_cdf(hi)), mass(cdf_hi - cdf_lo) {}

  double cdf(double z) const {
    if (z <= alpha) return 0.0;
    if (z >= beta) return 1.0;
    // P(Z <= z) = P(-Z >= -z) when mirrored.
    const double p = mirrored ? (cdf_hi - std_normal_cdf(-z)) / mass
                              : (std_normal_cdf(z) - cdf_lo) / mass;
    return std::clamp(p, 0.0, 1.0);
  }

  // p in [0, 1]; the ends are handled by the caller.
  double quantile(double p) const {
    // The target value of Phi on the interval worked on, Phi(lo) + q mass
    // with q = p (q = 1 - p when mirrored), is measured from the nearer end
    // so that neither a small p nor a small 1 - p is lost (1 - p is exact
    // for p >= 1/2).
    double target;
    if (!mirrored)
      target = p <= 0.5 ? cdf_lo + p * mass : cdf_hi - (1.0 - p) * mass;
    else
      target = p <= 0.5 ? cdf_hi - p * mass : cdf_lo + (1.0 - p) * mass;
    const double z = std_normal_quantile(target);
    return std::clamp(mirrored ? -z : z, alpha, beta);
  }

  double log_pdf(double z) const {
    if (!(z >= alpha && z <= beta)) return -kInf;
    return -0.5 * z * z - std::log(boost::math::constants::root_two_pi<double>()) -
           std::log(mass);
  }

  // Mean and variance (Johnson, Kotz and Balakrishnan 1994, ch. 13):
  // with l_a = phi(alpha) / mass, l_b = phi(beta) / mass,
  // E Z = l_a - l_b, Var Z = 1 + alpha l_a - beta l_b - (E Z)^2.
  double mean() const { return (std_normal_pdf(alpha) - std_normal_pdf(beta)) / mass; }
  double variance() const {
    const double l_a = std_normal_pdf(alpha) / mass, l_b = std_normal_pdf(beta) / mass;
    const double a_term = std::isinf(alpha) ? 0.0 : alpha * l_a;
    const double b_term = std::isinf(beta) ? 0.0 : beta * l_b;
    const double m = l_a - l_b;
    return std::max(0.0, 1.0 + a_term - b_term - m * m);
  }
};

// The standardised truncation of a normal (mean mu, sd sigma) to [lower, upper].
TruncatedStdNormal standardised(double mu, double sigma, double lower, double upper) {
  return TruncatedStdNormal((lower - mu) / sigma, (upper - mu) / sigma);
}

// A lognormal's truncation on the log scale (any lower <= 0 is no truncation).
TruncatedStdNormal standardised_log(const Distribution& d) {
  const double log_lower = d.lower > 0.0 ? std::log(d.lower) : -kInf;
  const double log_upper = d.upper == kInf ? kInf : std::log(d.upper);
  return standardised(d.a, d.b, log_lower, log_upper);
}

// log(max / min) of a log-uniform, accurate also when max / min is close to 1.
double log_ratio(double min, double max) { return std::log1p((max - min) / min); }

// atanh(t) - t = t^3/3 + t^5/5 + ... for |t| < 0.1, summed (no cancellation).
double atanh_minus_identity_series(double t) {
  const double t2 = t * t;
  double term = t * t2, sum = 0.0;
  for (int k = 3; term != 0.0 && std::abs(term) > 1e-17 * std::abs(sum); k += 2) {
    sum += term / k;
    term *= t2;
  }
  return sum;
}

bool untruncated(const Distribution& d) {
  const double lower_end = d.kind == DistributionKind::kLognormal ? 0.0 : -kInf;
  return d.lower <= lower_end && d.upper == kInf;
}

// Shortest round-trip decimal form ("0.039", "1e-06", "inf").
std::string shortest(double x) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

// A derived number to 4 significant digits ("0.262"), where the shortest
// round-trip text would show digits nobody typed.
std::string four_digits(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", x);
  return std::string(text);
}

bool fail_with(std::string* why, const std::string& reason) {
  if (why) *why = reason;
  return false;
}

}  // namespace

const char* distribution_name(DistributionKind kind) {
  switch (kind) {
    case DistributionKind::kFixed: return "fixed";
    case DistributionKind::kUniform: return "uniform";
    case DistributionKind::kLogUniform: return "log_uniform";
    case DistributionKind::kNormal: return "normal";
    case DistributionKind::kLognormal: return "lognormal";
  }
  return "unknown";
}

double Distribution::truncation_mass() const {
  if (kind == DistributionKind::kNormal) return standardised(a, b, lower, upper).mass;
  if (kind == DistributionKind::kLognormal) return standardised_log(*this).mass;
  return 1.0;
}

double Distribution::support_lower() const {
  switch (kind) {
    case DistributionKind::kFixed:
    case DistributionKind::kUniform:
    case DistributionKind::kLogUniform: return a;
    case DistributionKind::kNormal: return lower;
    case DistributionKind::kLognormal: return std::max(lower, 0.0);
  }
  return kNaN;
}

double Distribution::support_upper() const {
  switch (kind) {
    case DistributionKind::kFixed: return a;
    case DistributionKind::kUniform:
    case DistributionKind::kLogUniform: return b;
    case DistributionKind::kNormal:
    case DistributionKind::kLognormal: return upper;
  }
  return kNaN;
}

double Distribution::quantile(double p) const {
  if (!(p >= 0.0 && p <= 1.0))
    throw std::domain_error("Distribution::quantile: p = " + shortest(p) +
                            " is outside [0, 1] (" + describe() + ")");
  if (kind == DistributionKind::kFixed) return a;
  const double lo = support_lower(), hi = support_upper();
  if (p == 0.0 || p == 1.0) {
    const double end = p == 0.0 ? lo : hi;
    if (std::isinf(end))
      throw std::domain_error("Distribution::quantile: p = " + shortest(p) +
                              " maps to an infinite end of the support of " + describe());
    return end;
  }
  switch (kind) {
    case DistributionKind::kUniform: return std::clamp(a + p * (b - a), a, b);
    case DistributionKind::kLogUniform: return std::clamp(a * std::exp(p * log_ratio(a, b)), a, b);
    case DistributionKind::kNormal:
      return std::clamp(a + b * standardised(a, b, lower, upper).quantile(p), lo, hi);
    case DistributionKind::kLognormal:
      return std::clamp(std::exp(a + b * standardised_log(*this).quantile(p)), lo, hi);
    case DistributionKind::kFixed: break;
  }
  return kNaN;
}

double Distribution::cdf(double x) const {
  if (std::isnan(x)) return kNaN;
  switch (kind) {
    case DistributionKind::kFixed: return x < a ? 0.0 : 1.0;
    case DistributionKind::kUniform:
      if (x <= a) return 0.0;
      if (x >= b) return 1.0;
      return (x - a) / (b - a);
    case DistributionKind::kLogUniform:
      if (x <= a) return 0.0;
      if (x >= b) return 1.0;
      return log_ratio(a, x) / log_ratio(a, b);
    // The ends are compared in x: standardising may round a point just
    // outside onto the bound.
    case DistributionKind::kNormal:
      if (x <= lower) return 0.0;
      if (x >= upper) return 1.0;
      return standardised(a, b, lower, upper).cdf((x - a) / b);
    case DistributionKind::kLognormal:
      if (x <= 0.0 || x <= lower) return 0.0;
      if (x >= upper) return 1.0;
      return standardised_log(*this).cdf((std::log(x) - a) / b);
  }
  return kNaN;
}

double Distribution::log_pdf(double x) const {
  if (std::isnan(x)) return kNaN;
  switch (kind) {
    case DistributionKind::kFixed: return x == a ? 0.0 : -kInf;
    case DistributionKind::kUniform: return x >= a && x <= b ? -std::log(b - a) : -kInf;
    case DistributionKind::kLogUniform:
      return x >= a && x <= b ? -std::log(x) - std::log(log_ratio(a, b)) : -kInf;
    case DistributionKind::kNormal:
      if (x < lower || x > upper) return -kInf;
      return standardised(a, b, lower, upper).log_pdf((x - a) / b) - std::log(b);
    case DistributionKind::kLognormal: {
      if (!(x > 0.0) || x < lower || x > upper) return -kInf;
      const double log_x = std::log(x);
      return standardised_log(*this).log_pdf((log_x - a) / b) - std::log(b) - log_x;
    }
  }
  return kNaN;
}

double Distribution::mean() const {
  switch (kind) {
    case DistributionKind::kFixed: return a;
    case DistributionKind::kUniform: return 0.5 * (a + b);
    case DistributionKind::kLogUniform: return (b - a) / log_ratio(a, b);
    case DistributionKind::kNormal: return a + b * standardised(a, b, lower, upper).mean();
    case DistributionKind::kLognormal: {
      // E X = exp(mu + sigma^2 / 2) P(alpha - sigma <= Z <= beta - sigma) / P(alpha <= Z <= beta).
      const double m = std::exp(a + 0.5 * b * b);
      if (untruncated(*this)) return m;
      const TruncatedStdNormal t = standardised_log(*this);
      return m * std_normal_mass(t.alpha - b, t.beta - b) / t.mass;
    }
  }
  return kNaN;
}

double Distribution::sd() const {
  switch (kind) {
    case DistributionKind::kFixed: return 0.0;
    case DistributionKind::kUniform: return (b - a) / std::sqrt(12.0);
    case DistributionKind::kLogUniform: {
      // Var X = (b^2 - a^2) / (2 L) - ((b - a) / L)^2 with L = log(b / a)
      // = 2 atanh(t), t = (b - a) / (b + a); factored as
      // (b - a) / L * (b + a) / 2 * (atanh(t) - t) / atanh(t), free of
      // cancellation as b / a -> 1 (where it tends to the uniform's).
      const double t = (b - a) / (b + a), atanh_t = 0.5 * log_ratio(a, b);
      const double excess = t < 0.1 ? atanh_minus_identity_series(t) : atanh_t - t;
      return std::sqrt((b - a) / (2.0 * atanh_t) * 0.5 * (b + a) * excess / atanh_t);
    }
    case DistributionKind::kNormal:
      return b * std::sqrt(standardised(a, b, lower, upper).variance());
    case DistributionKind::kLognormal: {
      if (untruncated(*this)) return std::exp(a + 0.5 * b * b) * std::sqrt(std::expm1(b * b));
      // E X^k = exp(k mu + k^2 sigma^2 / 2) P(alpha - k sigma <= Z <= beta - k sigma) / mass.
      const TruncatedStdNormal t = standardised_log(*this);
      const double m1 = std::exp(a + 0.5 * b * b) * std_normal_mass(t.alpha - b, t.beta - b) / t.mass;
      const double m2 =
          std::exp(2.0 * a + 2.0 * b * b) * std_normal_mass(t.alpha - 2.0 * b, t.beta - 2.0 * b) / t.mass;
      return std::sqrt(std::max(0.0, m2 - m1 * m1));
    }
  }
  return kNaN;
}

std::string negligible_spread_problem(const Distribution& d, double reference) {
  if (d.kind == DistributionKind::kFixed) return "";
  const double mean = d.mean(), sd = d.sd();
  const double scale = std::max(std::abs(mean), std::isnan(reference) ? 0.0 : std::abs(reference));
  if (!std::isfinite(scale)) return "";  // a mean beyond doubles: refused where the median is tried
  const double lo = d.support_lower(), hi = d.support_upper();
  const double width = std::isfinite(lo) && std::isfinite(hi) ? hi - lo : kInf;
  const double limit = kMinRelativeSpread * scale;
  if (sd > limit && width > limit) return "";
  const bool by_reference = !std::isnan(reference) && std::abs(reference) > std::abs(mean);
  const std::string scale_text =
      by_reference ? "the configured value " + shortest(reference) : "its mean's size " + shortest(std::abs(mean));
  return d.describe() + " has sd " + four_digits(sd) +
         (std::isfinite(width) ? " on a support " + four_digits(width) + " wide" : std::string()) + ", not above " +
         shortest(kMinRelativeSpread) + " of " + scale_text + spread_rule_text();
}

std::string spread_rule_text() {
  return ": its runs would differ by rounding only (a distribution's sd and support width must exceed " +
         shortest(kMinRelativeSpread) +
         " of the larger of its mean's size and the parameter's configured value); use a fixed value";
}

bool Distribution::IsValid(std::string* why) const {
  const std::string name = distribution_name(kind);
  if (name == "unknown") return fail_with(why, "unknown distribution kind");
  const bool truncatable = kind == DistributionKind::kNormal || kind == DistributionKind::kLognormal;
  if (!truncatable && !(lower == -kInf && upper == kInf))
    return fail_with(why, name + ": truncation applies to normal and lognormal only (got [" +
                              shortest(lower) + ", " + shortest(upper) + "])");
  if (!std::isfinite(a)) return fail_with(why, name + ": parameter " + shortest(a) + " is not finite");
  if (kind == DistributionKind::kFixed) return true;
  if (!std::isfinite(b)) return fail_with(why, name + ": parameter " + shortest(b) + " is not finite");
  switch (kind) {
    case DistributionKind::kLogUniform:
      if (!(a > 0.0))
        return fail_with(why, "log_uniform: min (" + shortest(a) + ") must be positive");
      [[fallthrough]];
    case DistributionKind::kUniform:
      if (!(a < b))
        return fail_with(why, name + ": min (" + shortest(a) + ") must be less than max (" +
                                  shortest(b) + ")");
      if (!std::isfinite(b - a)) return fail_with(why, name + ": max - min overflows");
      break;
    case DistributionKind::kNormal:
    case DistributionKind::kLognormal: {
      const std::string sd_name = kind == DistributionKind::kNormal ? "sd" : "log_sd";
      if (!(b > 0.0))
        return fail_with(why, name + ": " + sd_name + " (" + shortest(b) + ") must be positive");
      if (!(lower < upper))
        return fail_with(why, name + ": truncation lower bound (" + shortest(lower) +
                                  ") must be less than the upper bound (" + shortest(upper) + ")");
      if (kind == DistributionKind::kLognormal && !(upper > 0.0))
        return fail_with(why, "lognormal: truncation upper bound (" + shortest(upper) +
                                  ") must be positive");
      const double mass = kind == DistributionKind::kNormal
                              ? standardised(a, b, lower, upper).mass
                              : standardised_log(*this).mass;
      if (!(mass >= kMinTruncationMass))
        return fail_with(why, name + ": the truncation interval [" + shortest(lower) + ", " +
                                  shortest(upper) + "] holds probability " + shortest(mass) +
                                  " (less than 1e-300)");
      break;
    }
    case DistributionKind::kFixed: break;
  }
  if (const std::string problem = negligible_spread_problem(*this); !problem.empty()) return fail_with(why, problem);
  return true;
}

std::string Distribution::describe() const {
  const std::string name = distribution_name(kind);
  std::string args;
  switch (kind) {
    case DistributionKind::kFixed: args = "value " + shortest(a); break;
    case DistributionKind::kUniform:
    case DistributionKind::kLogUniform: args = "min " + shortest(a) + ", max " + shortest(b); break;
    case DistributionKind::kNormal: args = "mean " + shortest(a) + ", sd " + shortest(b); break;
    case DistributionKind::kLognormal: {
      // The value's own mean and sd beside the parameters of its log.
      const double mean = std::exp(a + 0.5 * b * b), sd = mean * std::sqrt(std::expm1(b * b));
      args = "log_mean " + shortest(a) + ", log_sd " + shortest(b) + "; the value's mean " + four_digits(mean) +
             ", sd " + four_digits(sd) + (untruncated(*this) ? "" : " before truncation");
      break;
    }
  }
  const bool truncatable = kind == DistributionKind::kNormal || kind == DistributionKind::kLognormal;
  if (truncatable && !untruncated(*this)) {
    const double lo = support_lower();
    args += ", truncated to " + std::string(lo == -kInf ? "(" : "[") + shortest(lo) + ", " +
            shortest(upper) + (upper == kInf ? ")" : "]");
  }
  return name + "(" + args + ")";
}

Distribution fixed_value(double value) {
  Distribution d;
  d.kind = DistributionKind::kFixed;
  d.a = value;
  return d;
}

Distribution uniform(double min, double max) {
  Distribution d;
  d.kind = DistributionKind::kUniform;
  d.a = min;
  d.b = max;
  return d;
}

Distribution log_uniform(double min, double max) {
  Distribution d = uniform(min, max);
  d.kind = DistributionKind::kLogUniform;
  return d;
}

Distribution normal(double mean, double sd, double lower, double upper) {
  Distribution d;
  d.kind = DistributionKind::kNormal;
  d.a = mean;
  d.b = sd;
  d.lower = lower;
  d.upper = upper;
  return d;
}

Distribution lognormal(double log_mean, double log_sd, double lower, double upper) {
  Distribution d = normal(log_mean, log_sd, lower, upper);
  d.kind = DistributionKind::kLognormal;
  return d;
}

Distribution lognormal_from_moments(double mean, double sd) {
  if (!(mean > 0.0 && sd > 0.0 && std::isfinite(mean) && std::isfinite(sd)))
    return lognormal(kNaN, kNaN);
  const double ratio = sd / mean;
  const double log_variance = std::log1p(ratio * ratio);
  return lognormal(std::log(mean) - 0.5 * log_variance, std::sqrt(log_variance));
}

}  // namespace rover::study
