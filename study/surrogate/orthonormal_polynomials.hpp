// Orthonormal polynomial families of polynomial chaos expansions (Xiu &
// Karniadakis 2002; Sudret 2008) and the isoprobabilistic map of each input
// distribution onto the germ its family is orthonormal under:
//
//   uniform(a, b)                  Legendre on xi = (2x - a - b) / (b - a),  xi ~ U(-1, 1)
//   normal(m, s), not truncated    Hermite on xi = (x - m) / s,              xi ~ N(0, 1)
//   lognormal(m, s), not truncated Hermite on xi = (log x - m) / s
//   log_uniform(a, b)              Legendre on xi = 2 F(x) - 1, which is exactly linear in log x
//   truncated normal or lognormal  Legendre on xi = 2 F(x) - 1 (F from Distribution::cdf)
//   fixed                          the constant only (degree 0)
//
// Legendre: sqrt(2n + 1) P_n, orthonormal under U(-1, 1); (n + 1) P_{n+1} =
// (2n + 1) x P_n - n P_{n-1}. Hermite: He_n / sqrt(n!), the probabilists'
// polynomials, orthonormal under N(0, 1); He_{n+1} = x He_n - n He_{n-1}
// (Abramowitz & Stegun 1964, 22.7). Both are evaluated by their three-term
// recurrences, written directly on the normalised polynomials.
#pragma once

#include "study/estimators/distributions.hpp"

namespace rover::study {

enum class PolynomialFamily { kConstant, kLegendre, kHermite };

// "constant", "legendre", "hermite".
const char* polynomial_family_name(PolynomialFamily family);

// The family a distribution's input is expanded in (table above).
PolynomialFamily polynomial_family_for(const Distribution& distribution);

// The germ xi of x (table above); 0 for a fixed input. Assumes IsValid().
double to_germ(const Distribution& distribution, double x);

// values[n] = the orthonormal polynomial of degree n at xi, n = 0 .. max_degree
// (values must hold max_degree + 1 doubles). kConstant: values[0] = 1 and
// values[n > 0] = 0.
void orthonormal_polynomial_values(PolynomialFamily family, double xi, int max_degree,
                                   double* values);

}  // namespace rover::study
