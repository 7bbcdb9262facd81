// Summary of one scalar quantity of interest (a deflection, an at-rest error,
// ...) over the runs of a Monte Carlo study, each estimate with an interval
// that says how far N runs pin it down:
//
// * mean: Student-t interval mean -+ t_{(1+c)/2, N-1} s / sqrt(N) (exact for
//   normal values, by the central limit theorem otherwise);
// * standard deviation (N - 1): from kMinBootstrapSdSamples values on, the
//   bootstrap percentile interval (Efron & Tibshirani 1993, ch. 13) from
//   `bootstrap_resamples` resamples drawn with Boost.Random's mt19937_64 from
//   `seed` (portable: identical everywhere); below it, the chi-square
//   interval of a normal sample, [s sqrt((N-1)/chi2_{(1+c)/2, N-1}),
//   s sqrt((N-1)/chi2_{(1-c)/2, N-1})] (exact for normal values). A bootstrap
//   of so few values cannot resolve the sd: 2 values resample to sd 0 or s
//   only, and at 10 normal values its 95 % interval covers the sd 77 % of
//   the time (89 % at 30);
// * quantiles: the value by type-7 interpolation (Hyndman & Fan 1996, as
//   study/estimators/band_statistics.hpp), and the distribution-free interval
//   [X_(l), X_(u)] between two order statistics (Hahn & Meeker 1991, ch. 5):
//   for a continuous distribution, B = #{X_i <= x_p} ~ Binomial(N, p), so
//   P(X_(l) <= x_p < X_(u)) = P(l <= B <= u - 1) whatever the distribution.
//   The ranks are equal-tailed (each tail at most (1 - c)/2) when N allows;
//   when one tail cannot be met (X_(1) or X_(N) already too far in), the
//   interval is anchored at that extreme order statistic and the other rank
//   is chosen so that the coverage is still >= c. Binomial tails come from
//   Boost.Math.
//
// Such an interval exists only if even [X_(1), X_(N)] covers x_p with
// probability >= c, i.e. 1 - (1 - p)^N - p^N >= c: for the 0.135 % quantile
// (the -3 sigma level) at 95 %, N >= 2,218.
#pragma once

#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace rover::study {

// Fewer finite values than this: the sd's interval is the chi-square one.
inline constexpr int kMinBootstrapSdSamples = 30;

struct QuantileEstimate {
  double probability = 0;
  double value = std::numeric_limits<double>::quiet_NaN();  // type 7
  double lower = std::numeric_limits<double>::quiet_NaN();  // X_(lower_rank)
  double upper = std::numeric_limits<double>::quiet_NaN();  // X_(upper_rank)
  bool interval_exists = false;
  int lower_rank = 0, upper_rank = 0;  // 1-based order statistics (0: no interval)
  double coverage = std::numeric_limits<double>::quiet_NaN();  // exact P(l <= B <= u - 1)
};

struct QoiSummary {
  int samples = 0;  // finite values used
  double mean = std::numeric_limits<double>::quiet_NaN();
  double mean_lower = std::numeric_limits<double>::quiet_NaN();  // Student-t interval
  double mean_upper = std::numeric_limits<double>::quiet_NaN();
  double sd = std::numeric_limits<double>::quiet_NaN();  // sample sd (N - 1)
  double sd_lower = std::numeric_limits<double>::quiet_NaN();  // bootstrap percentile or chi-square interval
  double sd_upper = std::numeric_limits<double>::quiet_NaN();
  bool sd_interval_chi_square = false;  // fewer than kMinBootstrapSdSamples values: normal values assumed
  std::vector<QuantileEstimate> quantiles;  // one per requested probability, in that order
  // Plain words when N is too small for an interval, e.g. "the 0.135 % quantile
  // needs N >= 2,218 for a 95 % distribution-free interval"; several are
  // joined by "; ". Empty when every interval exists.
  std::string note;
};

// `values`: one per run; non-finite values (failed runs) are left out.
// `probabilities` in (0, 1); `confidence` in (0, 1); bootstrap_resamples >= 0
// (0: no sd interval, of either kind). The mean and sd intervals need N >= 2. Throws
// std::invalid_argument for arguments out of range, and WorkStopped once
// `stop` (if given; read at every resample) is set.
QoiSummary summarize_qoi(std::vector<double> values, const std::vector<double>& probabilities,
                         double confidence, int bootstrap_resamples, std::uint64_t seed,
                         const std::atomic<bool>* stop = nullptr);

// The chi-square interval of the sd of n >= 2 normal values whose sample sd
// is `sd`, at `confidence` (see above). Throws std::invalid_argument for n < 2
// or a confidence outside (0, 1).
std::pair<double, double> chi_square_sd_interval(double sd, int n, double confidence);

// The smallest N for which the distribution-free interval of quantile p exists
// at `confidence`: the smallest N with 1 - (1 - p)^N - p^N >= confidence.
// Throws std::invalid_argument unless 0 < p < 1 and 0 < confidence < 1, and
// std::overflow_error if N would not fit in an int.
int minimum_samples_for_quantile_interval(double p, double confidence);

}  // namespace rover::study
