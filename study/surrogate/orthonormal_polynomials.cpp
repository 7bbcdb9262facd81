// See orthonormal_polynomials.hpp.
#include "study/surrogate/orthonormal_polynomials.hpp"

#include <cmath>

namespace rover::study {
namespace {

bool is_truncated(const Distribution& d) {
  const bool lower_cut = d.kind == DistributionKind::kLognormal ? d.lower > 0.0 : std::isfinite(d.lower);
  return lower_cut || std::isfinite(d.upper);
}

// xi = 2 F(x) - 1, uniform on (-1, 1) whatever the distribution.
double probability_integral_germ(const Distribution& d, double x) { return 2.0 * d.cdf(x) - 1.0; }

}  // namespace

const char* polynomial_family_name(PolynomialFamily family) {
  switch (family) {
    case PolynomialFamily::kConstant: return "constant";
    case PolynomialFamily::kLegendre: return "legendre";
    case PolynomialFamily::kHermite: return "hermite";
  }
  return "unknown";
}

PolynomialFamily polynomial_family_for(const Distribution& d) {
  switch (d.kind) {
    case DistributionKind::kFixed: return PolynomialFamily::kConstant;
    case DistributionKind::kUniform:
    case DistributionKind::kLogUniform: return PolynomialFamily::kLegendre;
    case DistributionKind::kNormal:
    case DistributionKind::kLognormal:
      return is_truncated(d) ? PolynomialFamily::kLegendre : PolynomialFamily::kHermite;
  }
  return PolynomialFamily::kConstant;
}

double to_germ(const Distribution& d, double x) {
  switch (d.kind) {
    case DistributionKind::kFixed: return 0.0;
    case DistributionKind::kUniform: return (2.0 * x - d.a - d.b) / (d.b - d.a);
    case DistributionKind::kLogUniform:
      return 2.0 * std::log(x / d.a) / std::log(d.b / d.a) - 1.0;
    case DistributionKind::kNormal:
      return is_truncated(d) ? probability_integral_germ(d, x) : (x - d.a) / d.b;
    case DistributionKind::kLognormal:
      return is_truncated(d) ? probability_integral_germ(d, x) : (std::log(x) - d.a) / d.b;
  }
  return 0.0;
}

void orthonormal_polynomial_values(PolynomialFamily family, double xi, int max_degree,
                                   double* values) {
  values[0] = 1.0;
  if (max_degree < 1) return;
  if (family == PolynomialFamily::kConstant) {
    for (int n = 1; n <= max_degree; ++n) values[n] = 0.0;
    return;
  }
  if (family == PolynomialFamily::kLegendre) {
    // q_n = sqrt(2n + 1) P_n:  q_{n+1} = (sqrt((2n+1)(2n+3)) xi q_n - n sqrt((2n+3)/(2n-1)) q_{n-1}) / (n+1)
    values[1] = std::sqrt(3.0) * xi;
    for (int n = 1; n < max_degree; ++n) {
      const double a = std::sqrt((2.0 * n + 1.0) * (2.0 * n + 3.0));
      const double b = n * std::sqrt((2.0 * n + 3.0) / (2.0 * n - 1.0));
      values[n + 1] = (a * xi * values[n] - b * values[n - 1]) / (n + 1.0);
    }
    return;
  }
  // h_n = He_n / sqrt(n!):  h_{n+1} = (xi h_n - sqrt(n) h_{n-1}) / sqrt(n + 1)
  values[1] = xi;
  for (int n = 1; n < max_degree; ++n)
    values[n + 1] = (xi * values[n] - std::sqrt(static_cast<double>(n)) * values[n - 1]) /
                    std::sqrt(n + 1.0);
}

}  // namespace rover::study
