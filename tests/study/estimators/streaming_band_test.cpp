// Tests of study/estimators/streaming_band and study/runtime/ordered_sink: the band of curves fed
// one at a time equals band_statistics() on the whole matrix (mean and sd to
// rounding, the tail quantiles exactly) at every sample count, and feeding
// through an OrderedSink in any completion order gives bit-identical bands.
#include "study/estimators/streaming_band.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "study/estimators/band_statistics.hpp"
#include "study/runtime/ordered_sink.hpp"

namespace rover::study {
namespace {

// Curves like a drop test's B_l z: a common trend near 0.28 m plus a
// per-curve random offset and slope (sd ~ 1 mm), so the band varies over t.
Eigen::MatrixXd drop_like_curves(int n, int time_samples, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd curves(n, time_samples);
  for (int i = 0; i < n; ++i) {
    const double offset = 1e-3 * normal(engine), slope = 2e-3 * normal(engine);
    for (int t = 0; t < time_samples; ++t) {
      const double time = 0.1 * t;
      curves(i, t) = 0.28 - 0.01 * std::exp(-time) + offset + slope * time +
                     1e-4 * normal(engine);
    }
  }
  return curves;
}

std::vector<double> row(const Eigen::MatrixXd& m, Eigen::Index r) {
  std::vector<double> v(static_cast<std::size_t>(m.cols()));
  for (Eigen::Index c = 0; c < m.cols(); ++c) v[static_cast<std::size_t>(c)] = m(r, c);
  return v;
}

void expect_band_matches(const Band& streamed, const Band& reference) {
  ASSERT_EQ(streamed.samples_used, reference.samples_used);
  ASSERT_EQ(streamed.mean.size(), reference.mean.size());
  if (reference.samples_used == 1) {  // sd and mean -+ 3 sd undefined in both
    for (const Band* b : {&streamed, &reference})
      for (const auto* v : {&b->std, &b->lower, &b->upper})
        for (double x : *v) EXPECT_TRUE(std::isnan(x));
    EXPECT_EQ(streamed.mean, reference.mean);
    EXPECT_EQ(streamed.p00135, reference.p00135);
    return;
  }
  for (std::size_t t = 0; t < reference.mean.size(); ++t) {
    EXPECT_NEAR(streamed.mean[t], reference.mean[t], 1e-12 * std::abs(reference.mean[t])) << t;
    EXPECT_NEAR(streamed.std[t], reference.std[t], 1e-12 * reference.std[t]) << t;
    EXPECT_NEAR(streamed.lower[t], reference.lower[t], 1e-12 * std::abs(reference.lower[t])) << t;
    EXPECT_NEAR(streamed.upper[t], reference.upper[t], 1e-12 * std::abs(reference.upper[t])) << t;
    EXPECT_EQ(streamed.p00135[t], reference.p00135[t]) << t;  // exact, not approximate
    EXPECT_EQ(streamed.p99865[t], reference.p99865[t]) << t;
  }
}

TEST(StreamingBand, EqualsBandStatisticsAtEverySampleCount) {
  // Every n from 1 to 1500: the heaps fill up (4 values per tail here) and
  // the interpolated order statistics move, floor((n - 1) p) = 0, 1 and 2.
  const int n = 1500, time_samples = 3;
  const Eigen::MatrixXd curves = drop_like_curves(n, time_samples, 11);
  StreamingBand band(time_samples, n);
  EXPECT_EQ(band.kept_lowest(), 4u);
  for (int i = 0; i < n; ++i) {
    const std::vector<double> curve = row(curves, i);
    band.add(curve.data());
    const Band reference = band_statistics(curves.topRows(i + 1));
    if (i == 0) {  // one curve: its mean is the curve, its spread unmeasured
      for (double sd : band.result().std) EXPECT_TRUE(std::isnan(sd));
      EXPECT_EQ(band.result().mean, curve);
    }
    expect_band_matches(band.result(), reference);
    if (::testing::Test::HasFailure()) FAIL() << "first mismatch after " << i + 1 << " curves";
  }
}

TEST(StreamingBand, EqualsBandStatisticsWithFailedRunsLeftOut) {
  const int n = 3000, time_samples = 41;
  Eigen::MatrixXd curves = drop_like_curves(n, time_samples, 5);
  // Failed runs: a NaN or an infinity anywhere in the curve.
  for (int i = 7; i < n; i += 97) curves(i, (i * 13) % time_samples) = std::nan("");
  curves(100, 0) = std::numeric_limits<double>::infinity();
  const Band reference = band_statistics(curves);
  const int failed = n - reference.samples_used;
  ASSERT_EQ(failed, 32);

  StreamingBand band(time_samples, n);
  for (int i = 0; i < n; ++i) band.add(row(curves, i).data());
  EXPECT_EQ(band.curves_used(), static_cast<std::size_t>(reference.samples_used));
  EXPECT_EQ(band.curves_skipped(), static_cast<std::size_t>(failed));
  expect_band_matches(band.result(), reference);
}

TEST(StreamingBand, IdenticalCurvesGiveAZeroWidthBand) {
  const std::vector<double> curve = {0.281, -3.5, 1e6};
  StreamingBand band(curve.size(), 500);
  for (int i = 0; i < 500; ++i) band.add(curve.data());
  const Band b = band.result();
  EXPECT_EQ(b.mean, curve);
  EXPECT_EQ(b.std, std::vector<double>(3, 0.0));
  EXPECT_EQ(b.lower, curve);
  EXPECT_EQ(b.upper, curve);
  EXPECT_EQ(b.p00135, curve);
  EXPECT_EQ(b.p99865, curve);
}

TEST(StreamingBand, NoCurveGivesNaNAndTooManyCurvesThrow) {
  StreamingBand band(2, 3);
  const Band empty = band.result();
  EXPECT_EQ(empty.samples_used, 0);
  EXPECT_TRUE(std::isnan(empty.mean[0]) && std::isnan(empty.p99865[1]));
  const double nan_curve[2] = {1.0, std::nan("")}, good[2] = {1.0, 2.0};
  band.add(nan_curve);  // skipped curves count towards the limit too
  band.add(good);
  band.add(good);
  EXPECT_THROW(band.add(good), std::length_error);
  EXPECT_EQ(band.result().samples_used, 2);
  EXPECT_THROW(StreamingBand(2, 0), std::invalid_argument);
}

TEST(StreamingBand, MemoryIsBoundedByTimeSamplesAndTailCounts) {
  // For N = 10^5: floor(99999 * 0.00135) = 134, so type 7 reads order
  // statistics 134 and 135 and the 136 smallest values suffice; by symmetry
  // about as many of the largest.
  const std::size_t time_samples = 1001, max_curves = 100000;
  StreamingBand band(time_samples, max_curves);
  EXPECT_EQ(band.kept_lowest(), 136u);
  EXPECT_GE(band.kept_highest(), 136u);
  EXPECT_LE(band.kept_highest(), 137u);
  const std::size_t expected =
      sizeof(double) * time_samples * (band.kept_lowest() + band.kept_highest() + 3);
  EXPECT_GE(band.memory_bytes(), expected);
  EXPECT_LE(band.memory_bytes(), expected + 1024);
  EXPECT_LT(band.memory_bytes(), 2'300'000u);  // ~2.2 MB, against 800 MB for the N x T matrix

  const std::vector<double> curve(time_samples, 0.25);
  const std::size_t before = band.memory_bytes();
  for (int i = 0; i < 300; ++i) band.add(curve.data());
  EXPECT_EQ(band.memory_bytes(), before);
}

TEST(OrderedSink, ReleasesInIndexOrderWithinTheOutOfOrderWindow) {
  std::vector<int> released;
  std::vector<double> payloads;
  OrderedSink<double> sink([&](int index, double&& x) {
    released.push_back(index);
    payloads.push_back(x);
  });
  // Completion order of blocks of 8 finished in reverse: the window is 8.
  std::size_t most_buffered = 0;
  for (int block = 0; block < 10; ++block)
    for (int j = 7; j >= 0; --j) {
      const int index = 8 * block + j;
      if (index == 42)
        sink.skip(index);  // e.g. loaded from a checkpoint
      else
        sink.push(index, 0.5 * index);
      most_buffered = std::max(most_buffered, sink.buffered());
    }
  EXPECT_EQ(most_buffered, 7u);
  EXPECT_EQ(sink.buffered(), 0u);
  EXPECT_EQ(sink.next_index(), 80);
  std::vector<int> expected(80);
  std::iota(expected.begin(), expected.end(), 0);
  expected.erase(expected.begin() + 42);
  EXPECT_EQ(released, expected);
  for (std::size_t k = 0; k < released.size(); ++k) EXPECT_EQ(payloads[k], 0.5 * released[k]);

  EXPECT_THROW(sink.push(3, 1.0), std::invalid_argument);  // already released
  sink.push(90, 1.0);
  EXPECT_THROW(sink.push(90, 1.0), std::invalid_argument);  // already buffered
  EXPECT_THROW(sink.skip(90), std::invalid_argument);
  EXPECT_EQ(sink.buffered(), 1u);
}

TEST(OrderedSink, BandIsBitIdenticalWhateverTheCompletionOrder) {
  const int n = 400, time_samples = 9;
  const Eigen::MatrixXd curves = drop_like_curves(n, time_samples, 3);
  StreamingBand in_order(time_samples, n);
  for (int i = 0; i < n; ++i) in_order.add(row(curves, i).data());
  const Band expected = in_order.result();

  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    // A completion order of a farm: a random permutation.
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), std::mt19937_64(seed));
    StreamingBand streamed(time_samples, n);
    OrderedSink<std::vector<double>> sink(
        [&](int, std::vector<double>&& curve) { streamed.add(curve.data()); });
    for (const int i : order) sink.push(i, row(curves, i));
    const Band b = streamed.result();
    EXPECT_EQ(b.mean, expected.mean);
    EXPECT_EQ(b.std, expected.std);
    EXPECT_EQ(b.p00135, expected.p00135);
    EXPECT_EQ(b.p99865, expected.p99865);
  }
}

}  // namespace
}  // namespace rover::study
