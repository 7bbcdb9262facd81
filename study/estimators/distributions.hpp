// Probability distributions of the uncertain inputs of the studies (Monte
// Carlo bands, Sobol' and Morris sensitivity, calibration priors): quantiles
// for mapping sampling designs, CDFs, log densities for MCMC priors, moments.
//
// Normal and lognormal inputs may be truncated: the distribution conditioned
// on [lower, upper]. The truncated normal's CDF and quantile are computed on
// whichever side of the mean the interval lies, with Boost.Math's complemented
// CDF in the upper tail, so an interval far out in one tail (mean + 6 sd and
// beyond) keeps full relative precision instead of cancelling to 0 / 0
// (the truncated normal as in Johnson, Kotz and Balakrishnan 1994, ch. 13).
// A lognormal is a normal on log X, truncated to
// [log lower, log upper]. The log-uniform ("reciprocal") distribution is
// uniform in log X.
//
// Distribution is a plain value; every member is a pure function, so one
// object may be shared between threads. quantile, cdf, log_pdf, mean and sd
// assume IsValid() (they do not re-check it on every call);
// map_to_distributions (study/design/design.hpp) checks it once per column.
#pragma once

#include <limits>
#include <string>

namespace rover::study {

enum class DistributionKind { kFixed, kUniform, kLogUniform, kNormal, kLognormal };

// "fixed", "uniform", "log_uniform", "normal", "lognormal".
const char* distribution_name(DistributionKind kind);

struct Distribution {
  DistributionKind kind = DistributionKind::kFixed;
  // fixed: value a. uniform, log_uniform: support [a, b]. normal: mean a, sd b.
  // lognormal: log X ~ Normal(a, b).
  double a = 0.0, b = 0.0;
  // Truncation (normal, lognormal): the distribution conditioned on
  // [lower, upper]. Must stay at (-inf, inf) for the other kinds. For a
  // lognormal any lower <= 0 means "not truncated below".
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();

  // Inverse CDF. p in [0, 1]; p = 0 or 1 only where that end of the support
  // is finite (it returns the end), else throws std::domain_error; also throws
  // for p outside [0, 1] or NaN. For kFixed, a for every p. The result always
  // lies in [support_lower(), support_upper()].
  double quantile(double p) const;
  // P(X <= x); NaN for NaN x.
  double cdf(double x) const;
  // Log density; -inf outside the support, NaN for NaN x. For kFixed, the log
  // of the point mass: 0 at the value, -inf elsewhere. Computed in log space,
  // so it stays finite far in the tails (for MCMC priors).
  double log_pdf(double x) const;
  double mean() const;
  double sd() const;  // standard deviation
  // The probability of [lower, upper] under the untruncated distribution (1
  // for the kinds that are never truncated).
  double truncation_mass() const;
  double support_lower() const;  // may be -inf
  double support_upper() const;  // may be +inf

  // Ceres style: true, or false with the reason in *why (if not null):
  // finite parameters, min < max, sd > 0, log_uniform min > 0, truncation
  // only on normal / lognormal, lower < upper, a truncation interval
  // holding a representable probability (>= 1e-300), and a spread that the
  // samples resolve (negligible_spread_problem).
  bool IsValid(std::string* why) const;
  // e.g. "normal(mean 1.924, sd 0.039, truncated to [0, inf))"; numbers in
  // their shortest round-trip form.
  std::string describe() const;
};

// A spread below this share of a value's size is lost in the rounding of
// the samples (a double resolves about 2.2e-16 of it; the model's sums lose
// a few digits more): such an input is a fixed value in all but name.
inline constexpr double kMinRelativeSpread = 1e-12;

// The rule every kind but fixed obeys: "" if the distribution's sd, and the
// width of its support when finite, exceed kMinRelativeSpread of its scale,
// the larger of |mean| and |reference| (a parameter's configured value; NaN
// for none); else why not, naming the distribution and the rule. IsValid()
// applies it with no reference.
std::string negligible_spread_problem(const Distribution& d,
                                      double reference = std::numeric_limits<double>::quiet_NaN());

// The rule's words, for a caller that finds a spread too small before it
// has a distribution (": its runs would differ ... use a fixed value").
std::string spread_rule_text();

Distribution fixed_value(double value);
Distribution uniform(double min, double max);
Distribution log_uniform(double min, double max);
Distribution normal(double mean, double sd,
                    double lower = -std::numeric_limits<double>::infinity(),
                    double upper = std::numeric_limits<double>::infinity());
Distribution lognormal(double log_mean, double log_sd, double lower = 0.0,
                       double upper = std::numeric_limits<double>::infinity());
// The (untruncated) lognormal whose X has this mean and standard deviation:
// log_sd^2 = log(1 + (sd / mean)^2), log_mean = log(mean) - log_sd^2 / 2.
// Needs mean > 0 and sd > 0; otherwise the parameters are NaN and IsValid()
// says why. (The factories never throw; check IsValid().)
Distribution lognormal_from_moments(double mean, double sd);

}  // namespace rover::study
