// Sines and cosines of a fixed number of angles at once, for the joint
// rotations of the kinematic tree (kinematic_tree.cpp; docs/model.md §3),
// whose libm calls were a tenth of a right-hand side.
//
// Each angle x is reduced to r = x - k pi/2, |r| <= pi/4, with k the nearest
// integer to 2x/pi, by Cody and Waite's subtraction of pi/2 in three parts
// (those of fdlibm's __ieee754_rem_pio2, each exact when multiplied by k for
// |k| < 2^20); sin r and cos r are Cephes' minimax polynomials on
// [-pi/4, pi/4] (S. L. Moshier, Methods and Programs for Mathematical
// Functions, 1989), and k mod 4 picks and signs them. The same operations on
// every angle, without branches, so that the compiler vectorizes the loop.
// Results are within about one unit in the last place of std::sin and
// std::cos; an angle beyond kLargestReduced_rad, or not finite, is handed to
// std::sin and std::cos.
#pragma once

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>

namespace rover {

template <std::size_t N>
struct SinesCosines {
  std::array<double, N> sin, cos;
};

// Angles whose k stays below 2^20 (k pi/2 is then exact in the first part).
inline constexpr double kLargestReduced_rad = 1.0e6;

template <std::size_t N>
void sines_and_cosines(const std::array<double, N>& angle, SinesCosines<N>& out) {
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kPiOver2Part1 = 1.57079632673412561417e+00;  // first 33 bits of pi/2
  constexpr double kPiOver2Part2 = 6.07710050630396597660e-11;  // next 33 bits
  constexpr double kPiOver2Part3 = 2.02226624871116645580e-21;  // the rest, to 2^-120
  constexpr double kRoundingShift = 6755399441055744.0;         // 1.5 * 2^52: rounds to an integer
  constexpr double s1 = -1.66666666666666307295e-1, s2 = 8.33333333332211858878e-3,
                   s3 = -1.98412698295895385996e-4, s4 = 2.75573136213857245213e-6,
                   s5 = -2.50507477628578072866e-8, s6 = 1.58962301576546568060e-10;
  constexpr double c1 = 4.16666666666665929218e-2, c2 = -1.38888888888730564116e-3,
                   c3 = 2.48015872888517045348e-5, c4 = -2.75573141792967388112e-7,
                   c5 = 2.08757008419747316778e-9, c6 = -1.13585365213876817300e-11;
  for (std::size_t i = 0; i < N; ++i) {
    const double x = angle[i];
    const double shifted = x * kTwoOverPi + kRoundingShift;
    const double k = shifted - kRoundingShift;
    // k mod 4 is in the low bits of the shifted sum's mantissa.
    const std::uint64_t quadrant = std::bit_cast<std::uint64_t>(shifted);
    const double r = ((x - k * kPiOver2Part1) - k * kPiOver2Part2) - k * kPiOver2Part3;
    const double z = r * r;
    const double sin_r = r + r * z * (s1 + z * (s2 + z * (s3 + z * (s4 + z * (s5 + z * s6)))));
    const double cos_r = 1.0 - 0.5 * z + z * z * (c1 + z * (c2 + z * (c3 + z * (c4 + z * (c5 + z * c6)))));
    // An odd quadrant swaps sine and cosine (bit masks, which vectorize
    // where a conditional select does not); quadrants 2, 3 negate the sine
    // and 1, 2 the cosine.
    const std::uint64_t odd = std::uint64_t{0} - (quadrant & 1);
    const std::uint64_t sin_bits = std::bit_cast<std::uint64_t>(sin_r), cos_bits = std::bit_cast<std::uint64_t>(cos_r);
    out.sin[i] = std::bit_cast<double>(((sin_bits & ~odd) | (cos_bits & odd)) ^ ((quadrant & 2) << 62));
    out.cos[i] = std::bit_cast<double>(((cos_bits & ~odd) | (sin_bits & odd)) ^ (((quadrant + 1) & 2) << 62));
  }
  for (std::size_t i = 0; i < N; ++i)
    if (!(std::abs(angle[i]) <= kLargestReduced_rad)) {
      out.sin[i] = std::sin(angle[i]);
      out.cos[i] = std::cos(angle[i]);
    }
}

}  // namespace rover
