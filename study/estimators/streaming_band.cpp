// See streaming_band.hpp.
#include "study/estimators/streaming_band.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

namespace rover::study {
namespace {

// The tail levels of band_statistics(): the 3-sigma levels of a normal.
constexpr double kLowerLevel = 0.00135;
constexpr double kUpperLevel = 0.99865;

// Type-7 interpolation among n sorted values, as quantile() computes it:
// x[lo] + weight * (x[hi] - x[lo]).
struct Type7 {
  std::size_t lo, hi;
  double weight;
};

Type7 type7(std::size_t n, double p) {
  const double h = (static_cast<double>(n) - 1.0) * p;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  return {lo, std::min(lo + 1, n - 1), h - static_cast<double>(lo)};
}

// How many of the smallest (largest) values type-7 interpolation at p can need
// for any n <= max_curves: the largest hi + 1 (n - lo) over n.
std::size_t smallest_needed(std::size_t max_curves, double p) {
  std::size_t k = 1;
  for (std::size_t n = 1; n <= max_curves; ++n) k = std::max(k, type7(n, p).hi + 1);
  return k;
}

std::size_t largest_needed(std::size_t max_curves, double p) {
  std::size_t k = 1;
  for (std::size_t n = 1; n <= max_curves; ++n) k = std::max(k, n - type7(n, p).lo);
  return k;
}

// Offers x to a bounded heap of `size` elements (capacity `capacity`) ordered
// by `less` (std::less: keeps the smallest values, its top the largest kept).
template <class Less>
void offer(double* heap, std::size_t size, std::size_t capacity, double x, Less less) {
  if (size < capacity) {
    heap[size] = x;
    std::push_heap(heap, heap + size + 1, less);
  } else if (less(x, heap[0])) {
    std::pop_heap(heap, heap + size, less);
    heap[size - 1] = x;
    std::push_heap(heap, heap + size, less);
  }
}

}  // namespace

StreamingBand::StreamingBand(std::size_t time_samples, std::size_t max_curves)
    : time_samples_(time_samples), max_curves_(max_curves) {
  if (max_curves == 0) throw std::invalid_argument("StreamingBand: max_curves must be positive");
  k_low_ = smallest_needed(max_curves, kLowerLevel);
  k_high_ = largest_needed(max_curves, kUpperLevel);
  shift_.assign(time_samples, 0.0);
  shifted_mean_.assign(time_samples, 0.0);
  m2_.assign(time_samples, 0.0);
  lowest_.assign(time_samples * k_low_, 0.0);
  highest_.assign(time_samples * k_high_, 0.0);
}

void StreamingBand::add(const double* curve) {
  if (used_ + skipped_ >= max_curves_)
    throw std::length_error("StreamingBand: more than the " + std::to_string(max_curves_) +
                            " curves it was sized for");
  if (!std::all_of(curve, curve + time_samples_, [](double x) { return std::isfinite(x); })) {
    ++skipped_;
    return;
  }
  const std::size_t kept = used_;  // values in each heap before this curve
  ++used_;
  const double n = static_cast<double>(used_);
  if (used_ == 1) std::copy(curve, curve + time_samples_, shift_.begin());
  for (std::size_t t = 0; t < time_samples_; ++t) {
    const double x = curve[t];
    const double y = x - shift_[t];
    const double delta = y - shifted_mean_[t];
    shifted_mean_[t] += delta / n;
    m2_[t] += delta * (y - shifted_mean_[t]);
    offer(&lowest_[t * k_low_], std::min(kept, k_low_), k_low_, x, std::less<double>());
    offer(&highest_[t * k_high_], std::min(kept, k_high_), k_high_, x, std::greater<double>());
  }
}

Band StreamingBand::result() const {
  Band band;
  band.samples_used = static_cast<int>(used_);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (auto* v : {&band.mean, &band.std, &band.lower, &band.upper, &band.p00135, &band.p99865})
    v->assign(time_samples_, nan);
  if (used_ == 0) return band;
  const double n = static_cast<double>(used_);
  const std::size_t low_count = std::min(used_, k_low_), high_count = std::min(used_, k_high_);
  const Type7 low = type7(used_, kLowerLevel), high = type7(used_, kUpperLevel);
  std::vector<double> ascending(low_count), descending(high_count);
  for (std::size_t t = 0; t < time_samples_; ++t) {
    const double mean = shift_[t] + shifted_mean_[t];
    const double sd = used_ > 1 ? std::sqrt(m2_[t] / (n - 1.0)) : nan;  // one curve has no spread to measure
    band.mean[t] = mean;
    band.std[t] = sd;
    band.lower[t] = mean - 3.0 * sd;
    band.upper[t] = mean + 3.0 * sd;

    // Order statistic j of all used values is ascending[j] for j < low_count
    // and descending[used_ - 1 - j] for used_ - 1 - j < high_count.
    std::copy_n(&lowest_[t * k_low_], low_count, ascending.begin());
    std::sort(ascending.begin(), ascending.end());
    band.p00135[t] =
        ascending[low.lo] + low.weight * (ascending[low.hi] - ascending[low.lo]);
    std::copy_n(&highest_[t * k_high_], high_count, descending.begin());
    std::sort(descending.begin(), descending.end(), std::greater<double>());
    const double a = descending[used_ - 1 - high.lo], b = descending[used_ - 1 - high.hi];
    band.p99865[t] = a + high.weight * (b - a);
  }
  return band;
}

std::size_t StreamingBand::memory_bytes_for(std::size_t time_samples, std::size_t max_curves) {
  const std::size_t heaps = smallest_needed(max_curves, kLowerLevel) + largest_needed(max_curves, kUpperLevel);
  return sizeof(StreamingBand) + time_samples * (3 + heaps) * sizeof(double);
}

std::size_t StreamingBand::memory_bytes() const {
  std::size_t doubles = 0;
  for (const auto* v : {&shift_, &shifted_mean_, &m2_, &lowest_, &highest_}) doubles += v->capacity();
  return sizeof(*this) + doubles * sizeof(double);
}

}  // namespace rover::study
