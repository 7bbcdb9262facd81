// Distributions (study/estimators/distributions.cpp): moments, CDFs and quantiles against
// closed forms and Boost.Math references, sampling through designs (sample
// moments, Kolmogorov-Smirnov), quadrature of the densities, deep-tail
// truncation and validation.
#include "study/estimators/distributions.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <boost/math/constants/constants.hpp>
#include <boost/math/distributions/lognormal.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/uniform.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/special_functions/erf.hpp>
#include <gtest/gtest.h>

#include "study/design/design.hpp"

namespace rover::study {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kPi = boost::math::constants::pi<double>();

// Upper tail of N(0, 1) through std::erfc (a route independent of the code's
// Boost normal distribution).
double upper_tail(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

struct Case {
  std::string label;
  Distribution d;
  std::function<double(double)> reference_cdf;  // from Boost.Math / erfc, not from d
  double mean = kNaN, sd = kNaN;                // closed forms where known (NaN: by quadrature only)
};

std::vector<Case> cases() {
  namespace bm = boost::math;
  std::vector<Case> out;
  out.push_back({"uniform", uniform(2.0, 5.0),
                 [](double x) { return bm::cdf(bm::uniform_distribution<double>(2.0, 5.0), std::clamp(x, 2.0, 5.0)); },
                 3.5, 3.0 / std::sqrt(12.0)});
  {
    const double a = 1e-3, b = 10.0, l = std::log(b / a);
    out.push_back({"log_uniform", log_uniform(a, b),
                   [=](double x) {
                     return bm::cdf(bm::uniform_distribution<double>(std::log(a), std::log(b)),
                                    std::clamp(std::log(x), std::log(a), std::log(b)));
                   },
                   (b - a) / l, std::sqrt((b * b - a * a) / (2.0 * l) - std::pow((b - a) / l, 2))});
  }
  out.push_back({"normal", normal(1.924, 0.039),
                 [](double x) { return bm::cdf(bm::normal_distribution<double>(1.924, 0.039), x); },
                 1.924, 0.039});
  // Half-normal: mean s sqrt(2 / pi), sd s sqrt(1 - 2 / pi).
  out.push_back({"half_normal", normal(0.0, 2.0, 0.0, kInf),
                 [](double x) {
                   return x <= 0 ? 0.0 : 2.0 * bm::cdf(bm::normal_distribution<double>(0.0, 2.0), x) - 1.0;
                 },
                 2.0 * std::sqrt(2.0 / kPi), 2.0 * std::sqrt(1.0 - 2.0 / kPi)});
  out.push_back({"normal_two_sided", normal(1.0, 0.5, 0.2, 1.5),
                 [](double x) {
                   const bm::normal_distribution<double> n(1.0, 0.5);
                   const double lo = bm::cdf(n, 0.2), hi = bm::cdf(n, 1.5);
                   return (bm::cdf(n, std::clamp(x, 0.2, 1.5)) - lo) / (hi - lo);
                 }});
  {
    // N(0, 1) truncated to [6, inf): mean = Mills ratio phi(6) / Q(6).
    const double lambda = std::exp(-18.0) / std::sqrt(2.0 * kPi) / upper_tail(6.0);
    out.push_back({"normal_tail_6sd", normal(0.0, 1.0, 6.0, kInf),
                   [](double x) { return x <= 6.0 ? 0.0 : 1.0 - upper_tail(x) / upper_tail(6.0); },
                   lambda, std::sqrt(1.0 + 6.0 * lambda - lambda * lambda)});
  }
  // N(10, 2) truncated to [mean + 6 sd, mean + 7 sd].
  out.push_back({"normal_band_6_7sd", normal(10.0, 2.0, 22.0, 24.0), [](double x) {
                   const double z = std::clamp((x - 10.0) / 2.0, 6.0, 7.0);
                   return (upper_tail(6.0) - upper_tail(z)) / (upper_tail(6.0) - upper_tail(7.0));
                 }});
  out.push_back({"lognormal", lognormal(0.2, 0.5),
                 [](double x) { return x <= 0 ? 0.0 : bm::cdf(bm::lognormal_distribution<double>(0.2, 0.5), x); },
                 std::exp(0.2 + 0.125), std::exp(0.2 + 0.125) * std::sqrt(std::exp(0.25) - 1.0)});
  out.push_back({"lognormal_from_moments", lognormal_from_moments(2.0, 0.3),
                 [](double x) {
                   const double s2 = std::log(1.0 + 0.0225);
                   return x <= 0 ? 0.0
                                 : bm::cdf(bm::lognormal_distribution<double>(std::log(2.0) - 0.5 * s2, std::sqrt(s2)), x);
                 },
                 2.0, 0.3});
  out.push_back({"lognormal_truncated", lognormal(0.0, 0.5, 0.8, 2.0), [](double x) {
                   const bm::lognormal_distribution<double> l(0.0, 0.5);
                   const double lo = bm::cdf(l, 0.8), hi = bm::cdf(l, 2.0);
                   return (bm::cdf(l, std::clamp(x, 0.8, 2.0)) - lo) / (hi - lo);
                 }});
  return out;
}

// Integral of f over the distribution's support, cut where 1e-13 of the mass remains.
double integrate(const Distribution& d, const std::function<double(double)>& f) {
  const double lo = std::isinf(d.support_lower()) ? d.quantile(1e-13) : d.support_lower();
  const double hi = std::isinf(d.support_upper()) ? d.quantile(1.0 - 1e-13) : d.support_upper();
  auto integrand = [&](double x) { return f(x) * std::exp(d.log_pdf(x)); };
  return boost::math::quadrature::gauss_kronrod<double, 31>::integrate(integrand, lo, hi, 20, 1e-13);
}

std::vector<double> mapped_column(const Distribution& d, DesignType type, int n, std::uint64_t seed) {
  const DesignMatrix x = map_to_distributions(unit_design(type, n, 1, seed), {d});
  return std::vector<double>(x.data(), x.data() + x.size());
}

TEST(Distributions, Names) {
  EXPECT_STREQ(distribution_name(DistributionKind::kFixed), "fixed");
  EXPECT_STREQ(distribution_name(DistributionKind::kUniform), "uniform");
  EXPECT_STREQ(distribution_name(DistributionKind::kLogUniform), "log_uniform");
  EXPECT_STREQ(distribution_name(DistributionKind::kNormal), "normal");
  EXPECT_STREQ(distribution_name(DistributionKind::kLognormal), "lognormal");
}

TEST(Distributions, AllCasesAreValid) {
  for (const Case& c : cases()) {
    std::string why;
    EXPECT_TRUE(c.d.IsValid(&why)) << c.label << ": " << why;
  }
}

TEST(Distributions, MomentsMatchClosedForms) {
  for (const Case& c : cases()) {
    if (std::isnan(c.mean)) continue;
    EXPECT_NEAR(c.d.mean(), c.mean, 1e-12 * std::abs(c.mean)) << c.label;
    EXPECT_NEAR(c.d.sd(), c.sd, 1e-9 * c.sd) << c.label;
  }
}

TEST(Distributions, DensityIntegratesToOneAndGivesTheMoments) {
  for (const Case& c : cases()) {
    const double mass = integrate(c.d, [](double) { return 1.0; });
    const double first = integrate(c.d, [](double x) { return x; });
    const double m = c.d.mean();
    const double second_central = integrate(c.d, [m](double x) { return (x - m) * (x - m); });
    EXPECT_NEAR(mass, 1.0, 1e-9) << c.label;
    EXPECT_NEAR(first, m, 1e-9 * (std::abs(m) + c.d.sd())) << c.label;
    EXPECT_NEAR(std::sqrt(second_central), c.d.sd(), 1e-7 * c.d.sd()) << c.label;
  }
}

TEST(Distributions, CdfMatchesTheReference) {
  for (const Case& c : cases()) {
    for (int k = 1; k < 100; ++k) {
      const double x = c.d.quantile(k / 100.0);
      EXPECT_NEAR(c.d.cdf(x), c.reference_cdf(x), 1e-12) << c.label << " at x = " << x;
    }
  }
}

TEST(Distributions, LatinHypercubeSampleMomentsMatch) {
  const int n = 20000;
  for (const Case& c : cases()) {
    const std::vector<double> x = mapped_column(c.d, DesignType::kLatinHypercube, n, 11);
    double sum = 0.0;
    for (double v : x) sum += v;
    const double mean = sum / n;
    double squares = 0.0;
    for (double v : x) squares += (v - mean) * (v - mean);
    const double sd = std::sqrt(squares / (n - 1));
    // The mean within one standard error of plain Monte Carlo (the quantile
    // is monotone, so LHS does far better), the sd within 1 % (about two
    // Monte Carlo standard errors for the most kurtic case, log_uniform).
    EXPECT_NEAR(mean, c.d.mean(), c.d.sd() / std::sqrt(n)) << c.label;
    EXPECT_NEAR(sd, c.d.sd(), 0.01 * c.d.sd()) << c.label;
  }
}

TEST(Distributions, MonteCarloSampleHasKolmogorovSmirnovBelowOnePercentCriticalValue) {
  const int n = 20000;
  const double critical_1pc = 1.6276 / std::sqrt(n);  // asymptotic, P(D > c) = 0.01
  for (const Case& c : cases()) {
    std::vector<double> x = mapped_column(c.d, DesignType::kMonteCarlo, n, 2024);
    std::sort(x.begin(), x.end());
    double ks = 0.0;
    for (int i = 0; i < n; ++i) {
      const double f = c.reference_cdf(x[i]);
      ks = std::max({ks, f - static_cast<double>(i) / n, static_cast<double>(i + 1) / n - f});
    }
    EXPECT_LT(ks, critical_1pc) << c.label;
    EXPECT_GT(ks, 0.1 / std::sqrt(n)) << c.label << ": too good for independent draws";
  }
}

TEST(Distributions, QuantileAndCdfRoundTrip) {
  for (const Case& c : cases()) {
    for (double p : {1e-12, 1e-6, 0.01, 0.3, 0.5, 0.9, 0.999999, 1.0 - 1e-10}) {
      const double x = c.d.quantile(p);
      EXPECT_NEAR(c.d.cdf(x), p, 1e-9 * std::min(p, 1.0 - p) + 1e-14) << c.label << " p = " << p;
    }
    for (int k = 1; k < 50; ++k) {
      const double x = c.d.quantile(k / 50.0);
      EXPECT_NEAR(c.d.quantile(c.d.cdf(x)), x, 1e-12 * (std::abs(x) + c.d.sd())) << c.label;
    }
  }
}

TEST(Distributions, TruncationIsRespected) {
  for (const Case& c : cases()) {
    const double lo = c.d.support_lower(), hi = c.d.support_upper();
    for (double v : mapped_column(c.d, DesignType::kMonteCarlo, 5000, 3)) {
      EXPECT_GE(v, lo) << c.label;
      EXPECT_LE(v, hi) << c.label;
    }
    if (std::isfinite(lo)) {
      EXPECT_EQ(c.d.quantile(0.0), lo) << c.label;
      EXPECT_EQ(c.d.cdf(lo), 0.0) << c.label;
      EXPECT_EQ(c.d.log_pdf(std::nextafter(lo, -kInf)), -kInf) << c.label;
    } else {
      EXPECT_THROW(c.d.quantile(0.0), std::domain_error) << c.label;
    }
    if (std::isfinite(hi)) {
      EXPECT_EQ(c.d.quantile(1.0), hi) << c.label;
      EXPECT_EQ(c.d.cdf(hi), 1.0) << c.label;
      EXPECT_EQ(c.d.log_pdf(std::nextafter(hi, kInf)), -kInf) << c.label;
    } else {
      EXPECT_THROW(c.d.quantile(1.0), std::domain_error) << c.label;
    }
  }
  EXPECT_EQ(normal(0, 1, 0.5, 2).support_lower(), 0.5);
  EXPECT_EQ(lognormal(0, 1).support_lower(), 0.0);
  EXPECT_EQ(lognormal(0, 1).quantile(0.0), 0.0);
  EXPECT_EQ(lognormal(0, 1).log_pdf(-1.0), -kInf);
}

TEST(Distributions, QuantileRejectsProbabilitiesOutsideTheUnitInterval) {
  for (const Distribution& d : {uniform(0, 1), normal(0, 1), lognormal(0, 1), fixed_value(3)}) {
    EXPECT_THROW(d.quantile(-0.1), std::domain_error) << d.describe();
    EXPECT_THROW(d.quantile(1.1), std::domain_error) << d.describe();
    EXPECT_THROW(d.quantile(kNaN), std::domain_error) << d.describe();
  }
}

TEST(Distributions, TailTruncationAtSixSigmaKeepsFullPrecision) {
  // N(0, 1) | Z >= 6: Q(6) = 9.9e-10, so Phi(6) + p (1 - Phi(6)) would leave
  // the quantile with about 7 correct digits. The median solves Q(m) = Q(6) / 2.
  const Distribution d = normal(0.0, 1.0, 6.0, kInf);
  const double median =
      std::sqrt(2.0) * boost::math::erfc_inv(std::erfc(6.0 / std::sqrt(2.0)) / 2.0);
  EXPECT_NEAR(d.quantile(0.5), median, 1e-13 * median);
  double previous = 6.0;
  for (double p : {1e-9, 1e-3, 0.2, 0.7, 0.99, 1.0 - 1e-12}) {
    const double x = d.quantile(p);
    EXPECT_GT(x, previous) << p;
    previous = x;
  }
  // The largest p a design produces, 1 - 2^-53, still maps to a finite point.
  const double p_max = 1.0 - std::ldexp(1.0, -53);
  EXPECT_TRUE(std::isfinite(d.quantile(p_max)));
  EXPECT_GT(d.quantile(p_max), d.quantile(1.0 - 1e-12));
  EXPECT_NEAR(d.cdf(d.quantile(p_max)), p_max, 1e-15);
  // The same on the lower side, and on a scaled variable.
  const Distribution lower_tail = normal(5.0, 0.5, -kInf, 5.0 - 6.0 * 0.5);
  EXPECT_NEAR(lower_tail.quantile(0.5), 5.0 - 0.5 * median, 1e-13 * 5.0);
  // Far beyond: Z | Z >= 30 has mass 5e-198; its mean is the Mills ratio,
  // a + 1/a - 2/a^3 + 10/a^5 - ... for a = 30.
  const Distribution far = normal(0.0, 1.0, 30.0, kInf);
  std::string why;
  ASSERT_TRUE(far.IsValid(&why)) << why;
  const double a = 30.0;
  EXPECT_NEAR(far.mean(), a + 1 / a - 2 / std::pow(a, 3) + 10 / std::pow(a, 5), 1e-8);
  EXPECT_NEAR(far.cdf(far.quantile(0.5)), 0.5, 1e-12);
  EXPECT_TRUE(std::isfinite(far.log_pdf(30.5)));
}

TEST(Distributions, LogPdfStaysFiniteFarInTheTails) {
  // exp(-1250) underflows; its logarithm does not.
  EXPECT_DOUBLE_EQ(normal(0.0, 1.0).log_pdf(50.0), -1250.0 - 0.5 * std::log(2.0 * kPi));
  EXPECT_DOUBLE_EQ(normal(1.0, 2.0).log_pdf(1.0), -std::log(2.0) - 0.5 * std::log(2.0 * kPi));
  // Lognormal density at x = exp(mu): 1 / (x sigma sqrt(2 pi)).
  EXPECT_DOUBLE_EQ(lognormal(0.3, 0.5).log_pdf(std::exp(0.3)),
                   -0.3 - std::log(0.5) - 0.5 * std::log(2.0 * kPi));
  EXPECT_DOUBLE_EQ(uniform(1.0, 5.0).log_pdf(2.0), -std::log(4.0));
  EXPECT_DOUBLE_EQ(log_uniform(1.0, std::exp(2.0)).log_pdf(3.0), -std::log(3.0) - std::log(2.0));
}

TEST(Distributions, LogUniformIsUniformInTheLogarithm) {
  const Distribution d = log_uniform(1e-3, 1e3);
  EXPECT_NEAR(d.quantile(0.5), 1.0, 1e-14);
  EXPECT_NEAR(d.quantile(0.25), std::sqrt(1e-3), 1e-15);
  EXPECT_NEAR(d.cdf(10.0), 4.0 / 6.0, 1e-14);
  // As max / min -> 1 it tends to the uniform on [min, max]: mean and sd
  // differ from the uniform's by O(t^2) relatively, t = (max - min) / (max + min).
  const double a = 1e6, b = 1e6 * (1.0 + 1e-8);
  const Distribution narrow = log_uniform(a, b);
  EXPECT_NEAR(narrow.mean(), 0.5 * (a + b), 1e-15 * a);
  EXPECT_NEAR(narrow.sd(), (b - a) / std::sqrt(12.0), 1e-12 * (b - a));
  EXPECT_NEAR(narrow.cdf(a + 0.25 * (b - a)), 0.25, 1e-8);
  EXPECT_NEAR(narrow.quantile(0.25), a + 0.25 * (b - a), 1e-8 * (b - a));
}

TEST(Distributions, FixedValueIsAPointMass) {
  const Distribution d = fixed_value(2.5);
  for (double p : {0.0, 0.3, 1.0}) EXPECT_EQ(d.quantile(p), 2.5);
  EXPECT_EQ(d.cdf(2.4999), 0.0);
  EXPECT_EQ(d.cdf(2.5), 1.0);
  EXPECT_EQ(d.log_pdf(2.5), 0.0);
  EXPECT_EQ(d.log_pdf(2.6), -kInf);
  EXPECT_EQ(d.mean(), 2.5);
  EXPECT_EQ(d.sd(), 0.0);
  EXPECT_EQ(d.support_lower(), 2.5);
  EXPECT_EQ(d.support_upper(), 2.5);
}

TEST(Distributions, IsValidRejectsWithAReason) {
  struct Bad {
    Distribution d;
    std::string fragment;
  };
  Distribution truncated_uniform = uniform(0, 1);
  truncated_uniform.upper = 0.5;
  const std::vector<Bad> bad = {
      {uniform(1, 1), "min (1) must be less than max (1)"},
      {uniform(2, 1), "must be less than max"},
      {log_uniform(0, 1), "log_uniform: min (0) must be positive"},
      {log_uniform(-1, 1), "must be positive"},
      {normal(0, 0), "sd (0) must be positive"},
      {normal(0, -1), "must be positive"},
      {normal(0, 1, 2, 1), "lower bound (2) must be less than the upper bound (1)"},
      {normal(0, 1, 40, kInf), "less than 1e-300"},
      {lognormal(0, 1, 2, 1), "must be less than the upper bound"},
      {lognormal(0, 0), "log_sd (0) must be positive"},
      {lognormal(0, 1, -2, -1), "upper bound (-1) must be positive"},
      {lognormal_from_moments(-1, 1), "not finite"},
      {lognormal_from_moments(1, 0), "not finite"},
      {fixed_value(kNaN), "not finite"},
      {normal(kInf, 1), "not finite"},
      {truncated_uniform, "truncation applies to normal and lognormal only"},
  };
  for (const Bad& b : bad) {
    std::string why;
    EXPECT_FALSE(b.d.IsValid(&why)) << b.d.describe();
    EXPECT_NE(why.find(b.fragment), std::string::npos) << why;
    EXPECT_FALSE(b.d.IsValid(nullptr));
  }
  // A lognormal's lower bound <= 0 is no truncation at all.
  EXPECT_TRUE(lognormal(0, 1, -5, kInf).IsValid(nullptr));
  EXPECT_DOUBLE_EQ(lognormal(0, 1, -5, kInf).mean(), lognormal(0, 1).mean());
}

// One rule for every kind: sd and a finite support's width above 1e-12 of
// the larger of |mean| and a reference scale (a configured value).
TEST(Distributions, ASpreadTheSamplesCannotResolveIsRefused) {
  const std::vector<Distribution> negligible = {
      uniform(0.1, 0.1 * (1.0 + 1e-15)),
      log_uniform(1.0, 1.0 + 1e-14),
      normal(1.0, 1e-13),
      normal(0.14, 0.01, 0.14, 0.14 + 1e-15),  // a truncation keeping a sliver
      lognormal(0.0, 1e-14),
      lognormal(0.0, 1.0, 1.0, 1.0 + 1e-15),
  };
  for (const Distribution& d : negligible) {
    std::string why;
    EXPECT_FALSE(d.IsValid(&why)) << d.describe();
    EXPECT_NE(why.find("not above 1e-12 of its mean's size"), std::string::npos) << why;
    EXPECT_NE(why.find(d.describe()), std::string::npos) << why;
  }
  // Wide relative to itself, negligible next to the parameter's configured value.
  const Distribution tiny = uniform(1e-300, 1e-299);
  EXPECT_TRUE(tiny.IsValid(nullptr));
  EXPECT_EQ(negligible_spread_problem(tiny), "");
  EXPECT_NE(negligible_spread_problem(tiny, 0.14).find("not above 1e-12 of the configured value 0.14"),
            std::string::npos);
  // Spreads just above the rule pass.
  EXPECT_TRUE(uniform(1.0, 1.0 + 1e-10).IsValid(nullptr));
  EXPECT_TRUE(normal(0.14, 0.01, 0.14, 0.14 + 1e-9).IsValid(nullptr));
  EXPECT_TRUE(lognormal(0.0, 1e-10).IsValid(nullptr));
  EXPECT_EQ(negligible_spread_problem(normal(0.0, 1e-300)), "");  // no scale to compare with
}

TEST(Distributions, Describe) {
  EXPECT_EQ(normal(1.924, 0.039, 0.0, kInf).describe(),
            "normal(mean 1.924, sd 0.039, truncated to [0, inf))");
  EXPECT_EQ(normal(0, 1, -kInf, 3).describe(), "normal(mean 0, sd 1, truncated to (-inf, 3])");
  EXPECT_EQ(normal(0, 0.5).describe(), "normal(mean 0, sd 0.5)");
  EXPECT_EQ(uniform(0.1, 2).describe(), "uniform(min 0.1, max 2)");
  EXPECT_EQ(log_uniform(1e-06, 10).describe(), "log_uniform(min 1e-06, max 10)");
  EXPECT_EQ(lognormal(0, 0.25).describe(), "lognormal(log_mean 0, log_sd 0.25; the value's mean 1.032, sd 0.262)");
  EXPECT_EQ(lognormal(0, 0.25, 0, 4).describe(),
            "lognormal(log_mean 0, log_sd 0.25; the value's mean 1.032, sd 0.262 before truncation, truncated to [0, 4])");
  EXPECT_EQ(fixed_value(3).describe(), "fixed(value 3)");
}

}  // namespace
}  // namespace rover::study
