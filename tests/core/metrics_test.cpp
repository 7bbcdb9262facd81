// Metrics of docs/model.md §8 (core/metrics.cpp): RMS difference between
// curves sampled differently, linear interpolation, and the deflection and
// at-rest errors (paper eqs. 10-11) on curves built by hand.
#include "core/metrics.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace rover {
namespace {

std::vector<double> linspace(double a, double b, int n) {
  std::vector<double> t(n);
  for (int i = 0; i < n; ++i) t[i] = a + (b - a) * i / (n - 1);
  return t;
}

template <class F>
std::vector<double> sample(const std::vector<double>& t, F f) {
  std::vector<double> y;
  for (double x : t) y.push_back(f(x));
  return y;
}

TEST(Metrics, InterpolateIsLinearAndClampsAtTheEnds) {
  const std::vector<double> t{0.0, 0.1, 0.35, 1.0}, y{1.0, 3.0, -2.0, 0.5};
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_EQ(interpolate(t, y, t[i]), y[i]);
  EXPECT_DOUBLE_EQ(interpolate(t, y, 0.05), 2.0);
  EXPECT_NEAR(interpolate(t, y, 0.2), 3.0 + (0.1 / 0.25) * (-5.0), 1e-14);
  EXPECT_DOUBLE_EQ(interpolate(t, y, 0.675), -0.75);
  EXPECT_EQ(interpolate(t, y, -1.0), 1.0);
  EXPECT_EQ(interpolate(t, y, 7.0), 0.5);
  // A straight line is reproduced exactly anywhere inside.
  const std::vector<double> tl = linspace(-1.0, 2.0, 7), yl = sample(tl, [](double x) { return 4.0 - 3.0 * x; });
  for (double x = -1.0; x <= 2.0; x += 0.0137) EXPECT_NEAR(interpolate(tl, yl, x), 4.0 - 3.0 * x, 1e-13);
}

TEST(Metrics, RmsOfAConstantOffsetIsTheOffset) {
  // Lines interpolate exactly, so an offset of 0.3 gives RMS 0.3 whatever the sampling.
  const std::vector<double> ta = linspace(0.0, 2.0, 101), tb = linspace(-0.5, 1.5, 37);
  const auto a = sample(ta, [](double t) { return 2.0 * t - 1.0; });
  const auto b = sample(tb, [](double t) { return 2.0 * t - 1.0 + 0.3; });
  EXPECT_NEAR(rms_difference(ta, a, tb, b), 0.3, 1e-12);
  EXPECT_NEAR(rms_difference(tb, b, ta, a), 0.3, 1e-12);
  EXPECT_EQ(rms_difference(ta, a, ta, a), 0.0);
}

TEST(Metrics, RmsOfAShiftedSineMatchesTheAnalyticValue) {
  // sin(t + delta) - sin(t) = 2 sin(delta / 2) cos(t + delta / 2): over whole
  // periods its RMS is sqrt(2) |sin(delta / 2)|.
  const double delta = 0.2, two_pi = 2.0 * std::numbers::pi;
  const std::vector<double> ta = linspace(0.0, two_pi, 2001);
  const std::vector<double> tb = linspace(-0.3, two_pi + 0.4, 1517);  // other sampling, wider
  const auto a = sample(ta, [](double t) { return std::sin(t); });
  const auto b = sample(tb, [&](double t) { return std::sin(t + delta); });
  const double rms = rms_difference(ta, a, tb, b);
  EXPECT_NEAR(rms, std::sqrt(2.0) * std::sin(delta / 2.0), 1e-4);
  // The same sum taken by hand at a's samples with b exact: only b's
  // interpolation error (h^2 / 8 max|b''| = 3e-6) remains.
  double sum = 0.0;
  for (double t : ta) sum += std::pow(std::sin(t + delta) - std::sin(t), 2);
  EXPECT_NEAR(rms, std::sqrt(sum / static_cast<double>(ta.size())), 5e-6);
}

TEST(Metrics, RmsUsesOnlyTheCommonInterval) {
  // b covers [0.5, 1] of a's [0, 2]; a differs wildly outside, which must not count.
  const std::vector<double> ta = linspace(0.0, 2.0, 201), tb = linspace(0.5, 1.0, 11);
  const auto a = sample(ta, [](double t) { return t >= 0.5 && t <= 1.0 ? 0.0 : 1e6; });
  const auto b = sample(tb, [](double) { return 0.25; });
  EXPECT_NEAR(rms_difference(ta, a, tb, b), 0.25, 1e-12);
}

TEST(Metrics, BadCurvesAreRefused) {
  const std::vector<double> t1{0.0, 1.0, 2.0}, y1{0.0, 1.0, 2.0};
  const std::vector<double> t2{3.0, 4.0, 5.0}, y2{0.0, 1.0, 2.0};
  EXPECT_THROW(rms_difference(t1, y1, t2, y2), std::invalid_argument);  // no overlap
  EXPECT_THROW(rms_difference(t2, y2, t1, y1), std::invalid_argument);
  const std::vector<double> t_back{0.0, 2.0, 1.0}, t_flat{0.0, 1.0, 1.0}, short_t{0.0}, short_y{1.0};
  EXPECT_THROW(rms_difference(t_back, y1, t1, y1), std::invalid_argument);
  EXPECT_THROW(rms_difference(t1, y1, t_flat, y1), std::invalid_argument);
  EXPECT_THROW(rms_difference(short_t, short_y, t1, y1), std::invalid_argument);
  EXPECT_THROW(rms_difference(t1, short_y, t1, y1), std::invalid_argument);  // sizes differ
  EXPECT_THROW(deflection_error(t_back, y1, t1, y1), std::invalid_argument);
  EXPECT_THROW(at_rest_error(t1, y1, t_flat, y1), std::invalid_argument);
}

// A drop-test-like B_l z: falls, bottoms out at z_min at t_min, settles at z_rest.
struct Drop {
  std::vector<double> t, z;
};
Drop drop_curve(double z0, double z_min, double t_min, double z_rest, int n = 1001) {
  Drop d{linspace(0.0, 1.0, n), {}};
  for (double t : d.t)
    d.z.push_back(t <= t_min ? z0 + (z_min - z0) * t / t_min
                             : z_rest + (z_min - z_rest) * std::exp(-(t - t_min) / 0.05));
  return d;
}

TEST(Metrics, DeflectionAndAtRestErrorsFollowEquations10And11) {
  // Reference: bottoms out at 0.050, rests at 0.070 (deflection 0.020).
  const Drop ref = drop_curve(0.10, 0.050, 0.2, 0.070);
  // Judged: bottoms out at 0.045, rests at 0.072 (deflection 0.027).
  const Drop run = drop_curve(0.10, 0.045, 0.25, 0.072, 1333);
  const double rest_ref = interpolate(ref.t, ref.z, 1.0), rest = interpolate(run.t, run.z, 1.0);
  ASSERT_NEAR(rest_ref, 0.070, 2e-8);
  ASSERT_NEAR(rest, 0.072, 2e-8);
  EXPECT_NEAR(deflection_error(run.t, run.z, ref.t, ref.z), (rest - 0.045) / (rest_ref - 0.050) - 1.0, 1e-12);
  EXPECT_NEAR(deflection_error(run.t, run.z, ref.t, ref.z), 0.35, 1e-6);
  EXPECT_NEAR(at_rest_error(run.t, run.z, ref.t, ref.z), 0.072 / 0.070 - 1.0, 1e-6);
  // Identical curves: no error.
  EXPECT_EQ(deflection_error(ref.t, ref.z, ref.t, ref.z), 0.0);
  EXPECT_EQ(at_rest_error(ref.t, ref.z, ref.t, ref.z), 0.0);
  // eps_d compares deflections, so a common height offset does not change it;
  // eps_r compares heights, so it does.
  Drop run_up = run, ref_up = ref;
  for (double& z : run_up.z) z += 0.01;
  for (double& z : ref_up.z) z += 0.01;
  EXPECT_NEAR(deflection_error(run_up.t, run_up.z, ref_up.t, ref_up.z),
              deflection_error(run.t, run.z, ref.t, ref.z), 1e-12);
  EXPECT_NEAR(at_rest_error(run_up.t, run_up.z, ref_up.t, ref_up.z), 0.082 / 0.080 - 1.0, 1e-6);
}

TEST(Metrics, RestTimeIsInterpolatedBetweenSamples) {
  // Straight lines with samples that miss t_rest = 0.55: the values there are exact.
  const std::vector<double> t{0.0, 0.2, 0.5, 0.6, 1.0}, z{0.1, 0.04, 0.07, 0.08, 0.09};
  const std::vector<double> tr{0.0, 0.3, 0.7, 1.0}, zr{0.1, 0.05, 0.10, 0.1};
  const double z_r = 0.075, z_r_ref = 0.05 + (0.25 / 0.4) * 0.05;
  EXPECT_NEAR(at_rest_error(t, z, tr, zr, 0.55), z_r / z_r_ref - 1.0, 1e-12);
  EXPECT_NEAR(deflection_error(t, z, tr, zr, 0.55), (z_r - 0.04) / (z_r_ref - 0.05) - 1.0, 1e-12);
}

}  // namespace
}  // namespace rover
