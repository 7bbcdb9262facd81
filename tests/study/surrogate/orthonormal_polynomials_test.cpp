// Orthonormality of the polynomial families under their germs (Gauss
// quadrature), agreement with Boost.Math's Legendre and Hermite polynomials,
// and the isoprobabilistic maps of each kind of input.
#include "study/surrogate/orthonormal_polynomials.hpp"

#include <cmath>
#include <vector>

#include <boost/math/distributions/normal.hpp>
#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/special_functions/hermite.hpp>
#include <boost/math/special_functions/legendre.hpp>
#include <gtest/gtest.h>

namespace rover::study {
namespace {

constexpr int kMaxDegree = 12;
constexpr double kOrthonormalTolerance = 1e-10;

double value(PolynomialFamily family, double xi, int n) {
  std::vector<double> v(kMaxDegree + 1);
  orthonormal_polynomial_values(family, xi, kMaxDegree, v.data());
  return v[n];
}

TEST(OrthonormalPolynomials, LegendreOrthonormalUnderUniform) {
  for (int m = 0; m <= kMaxDegree; ++m)
    for (int n = 0; n <= kMaxDegree; ++n) {
      const auto f = [&](double xi) {
        return 0.5 * value(PolynomialFamily::kLegendre, xi, m) * value(PolynomialFamily::kLegendre, xi, n);
      };
      const double integral = boost::math::quadrature::gauss<double, 20>::integrate(f, -1.0, 1.0);
      EXPECT_NEAR(integral, m == n ? 1.0 : 0.0, kOrthonormalTolerance) << m << ", " << n;
    }
}

TEST(OrthonormalPolynomials, HermiteOrthonormalUnderStandardNormal) {
  const double inv_root_two_pi = 1.0 / std::sqrt(2.0 * M_PI);
  for (int m = 0; m <= kMaxDegree; ++m)
    for (int n = 0; n <= kMaxDegree; ++n) {
      const auto f = [&](double xi) {
        return inv_root_two_pi * std::exp(-0.5 * xi * xi) * value(PolynomialFamily::kHermite, xi, m) *
               value(PolynomialFamily::kHermite, xi, n);
      };
      const double integral = boost::math::quadrature::gauss_kronrod<double, 61>::integrate(
          f, -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), 15,
          1e-13);
      EXPECT_NEAR(integral, m == n ? 1.0 : 0.0, kOrthonormalTolerance) << m << ", " << n;
    }
}

TEST(OrthonormalPolynomials, AgreeWithBoostMath) {
  double factorial = 1.0;
  for (int n = 0; n <= kMaxDegree; ++n) {
    if (n > 0) factorial *= n;
    for (const double xi : {-0.93, -0.2, 0.0, 0.41, 0.999}) {
      EXPECT_NEAR(value(PolynomialFamily::kLegendre, xi, n),
                  std::sqrt(2.0 * n + 1.0) * boost::math::legendre_p(n, xi), 1e-11);
    }
    for (const double xi : {-3.1, -0.7, 0.0, 1.3, 4.2}) {
      // Probabilists' He_n(x) = 2^(-n/2) H_n(x / sqrt 2) from the physicists' H_n.
      const double he = std::pow(2.0, -0.5 * n) * boost::math::hermite(n, xi / std::sqrt(2.0));
      EXPECT_NEAR(value(PolynomialFamily::kHermite, xi, n), he / std::sqrt(factorial),
                  1e-10 * std::max(1.0, std::abs(he / std::sqrt(factorial))));
    }
  }
}

TEST(OrthonormalPolynomials, FamilyAndGermOfEachDistribution) {
  struct Case {
    Distribution d;
    PolynomialFamily family;
    bool gaussian_germ;  // xi = Phi^-1(u), else xi = 2u - 1
  };
  const std::vector<Case> cases{
      {uniform(-2.0, 5.0), PolynomialFamily::kLegendre, false},
      {log_uniform(0.01, 10.0), PolynomialFamily::kLegendre, false},
      {normal(1.5, 0.3), PolynomialFamily::kHermite, true},
      {lognormal(0.2, 0.5), PolynomialFamily::kHermite, true},
      {normal(1.5, 0.3, 1.0, 2.5), PolynomialFamily::kLegendre, false},
      {lognormal(0.2, 0.5, 0.5, 4.0), PolynomialFamily::kLegendre, false},
  };
  const boost::math::normal_distribution<double> std_normal;
  for (const Case& c : cases) {
    EXPECT_EQ(polynomial_family_for(c.d), c.family) << c.d.describe();
    for (const double u : {0.013, 0.25, 0.5, 0.77, 0.991}) {
      const double expected = c.gaussian_germ ? boost::math::quantile(std_normal, u) : 2.0 * u - 1.0;
      EXPECT_NEAR(to_germ(c.d, c.d.quantile(u)), expected, 1e-9) << c.d.describe() << " u " << u;
    }
  }
  EXPECT_EQ(polynomial_family_for(fixed_value(3.0)), PolynomialFamily::kConstant);
}

// E[psi_m(xi(X)) psi_n(xi(X))] = delta_mn under each input distribution,
// integrated against the distribution's own density (Distribution::log_pdf),
// independently of the germ formulas.
TEST(OrthonormalPolynomials, OrthonormalUnderEachInputDistribution) {
  constexpr int kDegree = 6;
  constexpr double kTolerance = 1e-8;
  const std::vector<Distribution> inputs{
      uniform(-2.0, 5.0),          log_uniform(0.01, 10.0),         normal(1.5, 0.3),
      lognormal(0.2, 0.5),         normal(1.5, 0.3, 1.0, 2.5),      lognormal(0.2, 0.5, 0.5, 4.0),
      normal(0.0, 1.0, 0.5)};
  for (const Distribution& d : inputs) {
    const PolynomialFamily family = polynomial_family_for(d);
    const double lo = d.support_lower(), hi = d.support_upper();
    for (int m = 0; m <= kDegree; ++m)
      for (int n = m; n <= kDegree; ++n) {
        const auto f = [&](double x) {
          const double log_density = d.log_pdf(x);
          if (!std::isfinite(log_density)) return 0.0;
          const double xi = to_germ(d, x);
          return std::exp(log_density) * value(family, xi, m) * value(family, xi, n);
        };
        // Split at the median so that narrow densities are not missed.
        const double mid = d.quantile(0.5);
        const double integral =
            boost::math::quadrature::gauss_kronrod<double, 61>::integrate(f, lo, mid, 20, 1e-13) +
            boost::math::quadrature::gauss_kronrod<double, 61>::integrate(f, mid, hi, 20, 1e-13);
        EXPECT_NEAR(integral, m == n ? 1.0 : 0.0, kTolerance) << d.describe() << " " << m << ", " << n;
      }
  }
}

}  // namespace
}  // namespace rover::study
