// See qoi_summary.hpp.
#include "study/estimators/qoi_summary.hpp"
#include "study/estimators/work_stopped.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_int_distribution.hpp>

#include "core/number_text.hpp"
#include "study/estimators/band_statistics.hpp"

namespace rover::study {
namespace {

using boost::math::binomial_distribution;

// "0.135" for 0.00135 as a percentage: enough digits, no trailing zeros.
std::string percent_text(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.12g", 100.0 * fraction);
  return text;
}

// 2218 -> "2,218"
std::string grouped(long long n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

// P(B <= k) and P(B > k) for B ~ Binomial(n, p); k = -1 and k = n allowed.
double lower_tail(const binomial_distribution<>& b, long long k) {
  if (k < 0) return 0.0;
  if (static_cast<double>(k) >= b.trials()) return 1.0;
  return boost::math::cdf(b, static_cast<double>(k));
}
double upper_tail(const binomial_distribution<>& b, long long k) {
  if (k < 0) return 1.0;
  if (static_cast<double>(k) >= b.trials()) return 0.0;
  return boost::math::cdf(boost::math::complement(b, static_cast<double>(k)));
}

// Largest k in [-1, n] with P(B <= k) <= q (P(B <= -1) = 0).
long long largest_with_lower_tail_at_most(const binomial_distribution<>& b, long long n, double q) {
  long long good = -1, bad = n + 1;  // invariant: tail(good) <= q < tail(bad)
  if (q >= 1.0) return n;
  while (bad - good > 1) {
    const long long mid = good + (bad - good) / 2;
    (lower_tail(b, mid) <= q ? good : bad) = mid;
  }
  return good;
}

// Smallest k in [0, n] with P(B > k) <= q (P(B > n) = 0).
long long smallest_with_upper_tail_at_most(const binomial_distribution<>& b, long long n,
                                           double q) {
  long long bad = -1, good = n;  // invariant: upper(bad) > q >= upper(good)
  while (good - bad > 1) {
    const long long mid = bad + (good - bad) / 2;
    (upper_tail(b, mid) <= q ? good : bad) = mid;
  }
  return good;
}

// Coverage of the widest interval [X_(1), X_(n)]: 1 - (1 - p)^n - p^n.
double widest_coverage(long long n, double p) {
  const binomial_distribution<> b(static_cast<double>(n), p);
  return 1.0 - lower_tail(b, 0) - upper_tail(b, n - 1);
}

void check_probability(double p, const char* what) {
  if (!(p > 0.0 && p < 1.0))
    throw std::invalid_argument(std::string(what) + " must be in (0, 1), got " + number_text(p));
}

// The interval of quantile p among n sorted values (see the header).
void quantile_interval(const std::vector<double>& sorted, double confidence, QuantileEstimate& q) {
  const auto n = static_cast<long long>(sorted.size());
  const double p = q.probability, alpha = 1.0 - confidence;
  if (n < 2 || widest_coverage(n, p) < confidence) return;
  const binomial_distribution<> b(static_cast<double>(n), p);
  // B >= l means X_(l) <= x_p; B <= u - 1 means x_p < X_(u).
  const long long a = largest_with_lower_tail_at_most(b, n, alpha / 2);       // l - 1
  const long long c = smallest_with_upper_tail_at_most(b, n, alpha / 2);      // u - 1
  long long l = a + 1, u = c + 1;
  if (a < 0) {  // even X_(1) is above x_p too often: anchor there
    l = 1;
    u = smallest_with_upper_tail_at_most(b, n, alpha - lower_tail(b, 0)) + 1;
  } else if (c > n - 1) {  // even X_(n) is below x_p too often
    u = n;
    l = largest_with_lower_tail_at_most(b, n, alpha - upper_tail(b, n - 1)) + 1;
  }
  const double coverage = 1.0 - lower_tail(b, l - 1) - upper_tail(b, u - 1);
  // Rounding at the existence boundary must not give a wrong claim.
  if (l < 1 || u > n || l >= u || coverage < confidence) return;
  q.interval_exists = true;
  q.lower_rank = static_cast<int>(l);
  q.upper_rank = static_cast<int>(u);
  q.lower = sorted[static_cast<std::size_t>(l - 1)];
  q.upper = sorted[static_cast<std::size_t>(u - 1)];
  q.coverage = coverage;
}

// The mean of x, summed as deviations from its first value: exactly that
// value when all are equal (a plain sum / n rounds 8 x 0.181 to another
// double, and the sd of a constant QoI would come out 3e-17, not 0).
double shifted_mean(const std::vector<double>& x) {
  double sum = 0.0;
  for (const double v : x) sum += v - x.front();
  return x.front() + sum / static_cast<double>(x.size());
}

double sample_sd(const std::vector<double>& x) {
  double sum = 0.0;
  for (const double v : x) sum += v - x.front();
  const double n = static_cast<double>(x.size()), shifted = sum / n;
  double ss = 0.0;
  for (const double v : x) ss += (v - x.front() - shifted) * (v - x.front() - shifted);
  return std::sqrt(ss / (n - 1.0));
}

// The bootstrap percentile interval of the sd of `values` (see the header).
std::pair<double, double> bootstrap_sd_interval(const std::vector<double>& values, double confidence, int resamples,
                                                std::uint64_t seed, const std::atomic<bool>* stop) {
  const std::size_t n = values.size();
  boost::random::mt19937_64 engine(seed);
  boost::random::uniform_int_distribution<std::size_t> pick(0, n - 1);
  std::vector<double> resample(n), sds(static_cast<std::size_t>(resamples));
  for (double& sd : sds) {
    stop_if_requested(stop, "QoI summary: bootstrap of the sd");
    for (double& x : resample) x = values[pick(engine)];
    sd = sample_sd(resample);
  }
  std::sort(sds.begin(), sds.end());
  return {quantile(sds, 0.5 - confidence / 2), quantile(sds, 0.5 + confidence / 2)};
}

}  // namespace

std::pair<double, double> chi_square_sd_interval(double sd, int n, double confidence) {
  check_probability(confidence, "confidence");
  if (n < 2) throw std::invalid_argument("chi_square_sd_interval: needs n >= 2, got " + std::to_string(n));
  const boost::math::chi_squared chi2(static_cast<double>(n - 1));
  const double dof = static_cast<double>(n - 1);
  return {sd * std::sqrt(dof / boost::math::quantile(chi2, 0.5 + confidence / 2)),
          sd * std::sqrt(dof / boost::math::quantile(chi2, 0.5 - confidence / 2))};
}

int minimum_samples_for_quantile_interval(double p, double confidence) {
  check_probability(p, "quantile probability");
  check_probability(confidence, "confidence");
  // widest_coverage(n) grows with n: double until it suffices, then bisect.
  long long bad = 1, good = 2;  // widest_coverage(1) = 0 < confidence
  while (widest_coverage(good, p) < confidence) {
    bad = good;
    good *= 2;
    if (good > 2LL * std::numeric_limits<int>::max())
      throw std::overflow_error("the " + percent_text(p) +
                                " % quantile needs more samples than an int holds");
  }
  while (good - bad > 1) {
    const long long mid = bad + (good - bad) / 2;
    (widest_coverage(mid, p) >= confidence ? good : bad) = mid;
  }
  if (good > std::numeric_limits<int>::max())
    throw std::overflow_error("the " + percent_text(p) +
                              " % quantile needs more samples than an int holds");
  return static_cast<int>(good);
}

QoiSummary summarize_qoi(std::vector<double> values, const std::vector<double>& probabilities,
                         double confidence, int bootstrap_resamples, std::uint64_t seed,
                         const std::atomic<bool>* stop) {
  check_probability(confidence, "confidence");
  for (const double p : probabilities) check_probability(p, "quantile probability");
  if (bootstrap_resamples < 0)
    throw std::invalid_argument("bootstrap_resamples must be >= 0, got " +
                                std::to_string(bootstrap_resamples));
  values.erase(std::remove_if(values.begin(), values.end(),
                              [](double v) { return !std::isfinite(v); }),
               values.end());
  std::sort(values.begin(), values.end());
  QoiSummary s;
  s.samples = static_cast<int>(values.size());
  const std::size_t n = values.size();
  for (const double p : probabilities) s.quantiles.push_back(QuantileEstimate{.probability = p});
  if (n == 0) {
    s.note = "no finite values";
    return s;
  }

  s.mean = shifted_mean(values);
  if (n >= 2) {
    s.sd = sample_sd(values);
    const boost::math::students_t t(static_cast<double>(n - 1));
    const double half = boost::math::quantile(t, 0.5 + confidence / 2) * s.sd /
                        std::sqrt(static_cast<double>(n));
    s.mean_lower = s.mean - half;
    s.mean_upper = s.mean + half;
  }
  if (n >= 2 && bootstrap_resamples > 0) {
    if (n < static_cast<std::size_t>(kMinBootstrapSdSamples)) {
      const auto [lower, upper] = chi_square_sd_interval(s.sd, static_cast<int>(n), confidence);
      s.sd_lower = lower;
      s.sd_upper = upper;
      s.sd_interval_chi_square = true;
    } else {
      const auto [lower, upper] = bootstrap_sd_interval(values, confidence, bootstrap_resamples, seed, stop);
      s.sd_lower = lower;
      s.sd_upper = upper;
    }
  }

  std::vector<std::string> notes;
  for (QuantileEstimate& q : s.quantiles) {
    q.value = quantile(values, q.probability);
    quantile_interval(values, confidence, q);
    if (!q.interval_exists)
      notes.push_back("the " + percent_text(q.probability) + " % quantile needs N >= " +
                      grouped(minimum_samples_for_quantile_interval(q.probability, confidence)) +
                      " for a " + percent_text(confidence) + " % distribution-free interval");
  }
  for (std::size_t i = 0; i < notes.size(); ++i) s.note += (i ? "; " : "") + notes[i];
  return s;
}

}  // namespace rover::study
