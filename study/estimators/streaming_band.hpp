// The confidence band of study/estimators/band_statistics.hpp (paper Fig. 13d: per time
// sample the mean, the standard deviation, mean -+ 3 sd and the empirical
// 0.135 % and 99.865 % quantiles) computed from curves fed one at a time, so
// that a study of N runs never holds its N x T curves.
//
// Mean and variance per time sample follow Welford (1962), on values shifted
// by the first curve used (as band_statistics() does: exact for identical
// curves, no cancellation for curves far from zero). The two tail quantiles
// are exact, not approximated: type-7 interpolation (Hyndman & Fan 1996) at
// probability p among n values needs only the order statistics
// floor((n - 1) p) and the one above it, so for at most max_curves curves it
// is enough to keep, per time sample, the k_low smallest values (a max-heap)
// and the k_high largest (a min-heap), with k the largest count any
// n <= max_curves can need.
//
// Memory: 8 * T * (k_low + k_high) bytes for the heaps plus 24 * T for the
// moments, with k_low, k_high ~ 0.00135 * max_curves + 2. For T = 1001 time
// samples and max_curves = 10^5: k = 136 each, about 2.2 MB (memory_bytes()).
//
// Fed the same curves in the same order, the result is bit-identical; feed
// them in index order (study/runtime/ordered_sink.hpp) for results independent of the
// number of MPI ranks. In index order, mean and sd equal band_statistics() on
// the same curves to about 1e-13 relative and the quantiles exactly.
#pragma once

#include <cstddef>
#include <vector>

#include "study/estimators/band_statistics.hpp"

namespace rover::study {

class StreamingBand {
 public:
  // Curves of `time_samples` values each; at most `max_curves` of them may be
  // added (used or skipped). Throws std::invalid_argument for max_curves = 0.
  StreamingBand(std::size_t time_samples, std::size_t max_curves);

  // One curve of time_samples values. A curve with a non-finite value (a
  // failed run) is not used and is counted in curves_skipped(). Throws
  // std::length_error when more than max_curves curves are added.
  void add(const double* curve);

  // The band of the curves used so far; samples_used = curves_used(). With no
  // curve used every value is NaN; with one, sd and the mean -+ 3 sd are NaN
  // (one curve has no spread to measure) and the quantiles are that curve.
  Band result() const;

  std::size_t curves_used() const { return used_; }
  std::size_t curves_skipped() const { return skipped_; }
  std::size_t time_samples() const { return time_samples_; }
  // Heap capacities per time sample (see the header comment).
  std::size_t kept_lowest() const { return k_low_; }
  std::size_t kept_highest() const { return k_high_; }
  // Bytes held by this object (its arrays included).
  std::size_t memory_bytes() const;
  // The bytes a band of `time_samples` and `max_curves` holds, before it is made.
  static std::size_t memory_bytes_for(std::size_t time_samples, std::size_t max_curves);

 private:
  std::size_t time_samples_, max_curves_, k_low_, k_high_;
  std::size_t used_ = 0, skipped_ = 0;
  std::vector<double> shift_;         // T: the first curve used
  std::vector<double> shifted_mean_;  // T: Welford mean of curve - shift
  std::vector<double> m2_;            // T: Welford sum of squared deviations
  std::vector<double> lowest_;        // T x k_low: max-heaps of the smallest values
  std::vector<double> highest_;       // T x k_high: min-heaps of the largest values
};

}  // namespace rover::study
