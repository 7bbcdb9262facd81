// The fixed-size products of the Rosenbrock stages (core/fixed_size_product.hpp)
// against Eigen's own, which they replace: alpha A x and y + c x agree with
// Eigen's arithmetic to the last bit, so the integrator's steps, and every
// result built on them, are those Eigen's products give. Random 23 x 23
// systems over many magnitudes (and 24 x 24, an even size).
#include "core/fixed_size_product.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace rover {
namespace {

constexpr int kSystems = 2000;

template <int N>
void expect_eigen_product_bits(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-6.0, 6.0);
  int differing = 0;
  for (int s = 0; s < kSystems; ++s) {
    Eigen::Matrix<double, N, N> a;
    Eigen::Matrix<double, N, 1> x, y;
    for (int i = 0; i < N; ++i) {
      x[i] = unit(rng) * std::pow(10.0, exponent(rng));
      y[i] = unit(rng);
      for (int j = 0; j < N; ++j) a(i, j) = unit(rng) * std::pow(10.0, exponent(rng));
    }
    const double alpha = unit(rng) * 1e3, c = unit(rng);
    // The expressions the integrator wrote before: alpha (A x), and A x.
    const Eigen::Matrix<double, N, 1> scaled = alpha * (a * x), plain = a * x;
    const Eigen::Matrix<double, N, 1> ours = fixed_size_product<N>(a, x, alpha), ours_plain = fixed_size_product<N>(a, x, 1.0);
    for (int i = 0; i < N; ++i) differing += (ours[i] != scaled[i]) + (ours_plain[i] != plain[i]);
    // And, whatever the bits, the product itself.
    EXPECT_LE((ours - scaled).norm(), 1e-12 * std::abs(alpha) * (a.cwiseAbs() * x.cwiseAbs()).norm()) << "system " << s;
    Eigen::Matrix<double, N, 1> summed = y, eigen_sum = y;
    add_scaled<N>(summed, c, x);
    eigen_sum += c * x;
    for (int i = 0; i < N; ++i) differing += summed[i] != eigen_sum[i];
  }
  EXPECT_EQ(differing, 0) << "coefficients that differ from Eigen's in some bit, N = " << N;
}

// The integrator's size. (Below about 8, Eigen evaluates a fixed-size
// product coefficient by coefficient, not by its kernel, and the bits differ.)
TEST(FixedSizeProduct, IsEigensProductToTheBit) {
  expect_eigen_product_bits<23>(1);
  expect_eigen_product_bits<24>(2);
}

}  // namespace
}  // namespace rover
