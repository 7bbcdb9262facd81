// See design.hpp.
#include "study/design/design.hpp"
#include "study/estimators/splitmix64.hpp"
#include "study/estimators/work_stopped.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <stdexcept>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/sobol.hpp>
#include <boost/random/uniform_int_distribution.hpp>

namespace rover::study {
namespace {

// Salts keeping the random streams of the design types apart.
constexpr std::uint64_t kLatinHypercubeSalt = 0x4C48532D4C484344ull;
constexpr std::uint64_t kSobolSalt = 0x534F424F4C4F5745ull;

// The digits of a unit coordinate kept: 52, so that the centre of the cell,
// (2 m + 1) 2^-53 with m < 2^52, is exact in a double and lies in (0, 1).
constexpr int kDigits = 52;

// The centre of the 2^-52 cell given by the top 52 bits of `bits`.
double open_unit_from_bits(std::uint64_t bits) {
  const std::uint64_t cell = bits >> (64 - kDigits);
  return std::ldexp(static_cast<double>(2 * cell + 1), -(kDigits + 1));
}

// Owen's nested uniform scramble of the top kDigits binary digits of x (a
// fraction in units of 2^-64): digit k (k = 0 most significant) is flipped
// by a random bit keyed by (key, k, digits 0 .. k-1 of x). Returns the
// scrambled digits, kDigits bits.
std::uint64_t owen_scramble(std::uint64_t x, std::uint64_t key) {
  std::uint64_t scrambled = 0;
  for (int k = 0; k < kDigits; ++k) {
    const std::uint64_t digit = (x >> (63 - k)) & 1u;
    const std::uint64_t prefix = k == 0 ? 0 : x >> (64 - k);  // < 2^k <= 2^51
    const std::uint64_t node = (static_cast<std::uint64_t>(k) << 58) | prefix;
    const std::uint64_t flip = splitmix64(key ^ splitmix64(node)) >> 63;
    scrambled = (scrambled << 1) | (digit ^ flip);
  }
  return scrambled;
}

void check_size(int samples, int dimensions) {
  if (samples < 1)
    throw std::invalid_argument("unit_design: samples must be >= 1, got " + std::to_string(samples));
  if (dimensions < 1)
    throw std::invalid_argument("unit_design: dimensions must be >= 1, got " +
                                std::to_string(dimensions));
}

DesignMatrix monte_carlo(int samples, int dimensions, std::uint64_t seed, const std::atomic<bool>* stop) {
  DesignMatrix u(samples, dimensions);
  const std::uint64_t seed_key = splitmix64(seed);
  for (int i = 0; i < samples; ++i) {
    if (i % kRowsBetweenStopChecks == 0) stop_if_requested(stop, "drawing the design");
    boost::random::mt19937_64 engine(splitmix64(seed_key ^ static_cast<std::uint64_t>(i)));
    for (int j = 0; j < dimensions; ++j) u(i, j) = open_unit_from_bits(engine());
  }
  return u;
}

DesignMatrix latin_hypercube(int samples, int dimensions, std::uint64_t seed, const std::atomic<bool>* stop) {
  DesignMatrix u(samples, dimensions);
  boost::random::mt19937_64 engine(splitmix64(seed ^ kLatinHypercubeSalt));
  std::vector<int> strata(static_cast<std::size_t>(samples));
  const double n = samples;
  for (int j = 0; j < dimensions; ++j) {
    // Fisher-Yates shuffle (Boost's integer distribution: the same on every platform).
    for (int i = 0; i < samples; ++i) strata[i] = i;
    for (int i = samples - 1; i > 0; --i) {
      if (i % kRowsBetweenStopChecks == 0) stop_if_requested(stop, "drawing the design");
      boost::random::uniform_int_distribution<int> pick(0, i);
      std::swap(strata[i], strata[pick(engine)]);
    }
    for (int i = 0; i < samples; ++i) {
      const int k = strata[i];
      double x = (k + open_unit_from_bits(engine())) / n;
      // Rounding can carry a jitter within an ulp of 1 onto the stratum's
      // upper edge (k + 1) / n; such a point goes to the stratum's centre.
      if (static_cast<int>(std::floor(x * n)) != k || !(x < 1.0)) x = (k + 0.5) / n;
      u(i, j) = x;
    }
  }
  return u;
}

DesignMatrix sobol(int samples, int dimensions, std::uint64_t seed, const std::atomic<bool>* stop) {
  if (dimensions > sobol_max_dimensions())
    throw std::invalid_argument("unit_design: a sobol design has at most " +
                                std::to_string(sobol_max_dimensions()) +
                                " dimensions (Boost's Joe-Kuo table), got " +
                                std::to_string(dimensions));
  std::vector<std::uint64_t> keys(static_cast<std::size_t>(dimensions));
  const std::uint64_t seed_key = splitmix64(seed ^ kSobolSalt);
  for (int j = 0; j < dimensions; ++j) keys[j] = splitmix64(seed_key + static_cast<std::uint64_t>(j));

  DesignMatrix u(samples, dimensions);
  // Point 0 of the sequence is the origin; boost::random::sobol skips it and
  // starts at point 1, in Gray-code order (points 0 .. 2^m - 1 are the same
  // set as in natural order, so every power-of-two prefix is a net).
  boost::random::sobol engine(static_cast<std::size_t>(dimensions));
  for (int i = 0; i < samples; ++i) {
    if (i % kRowsBetweenStopChecks == 0) stop_if_requested(stop, "drawing the design");
    for (int j = 0; j < dimensions; ++j) {
      const std::uint64_t x = i == 0 ? 0 : static_cast<std::uint64_t>(engine());
      u(i, j) = std::ldexp(static_cast<double>(2 * owen_scramble(x, keys[j]) + 1), -(kDigits + 1));
    }
  }
  return u;
}

}  // namespace

const char* design_type_name(DesignType type) {
  switch (type) {
    case DesignType::kMonteCarlo: return "monte_carlo";
    case DesignType::kLatinHypercube: return "latin_hypercube";
    case DesignType::kSobol: return "sobol";
    case DesignType::kGrid: return "grid";
  }
  return "unknown";
}

DesignType design_type_from_name(const std::string& name) {
  for (DesignType type : {DesignType::kMonteCarlo, DesignType::kLatinHypercube, DesignType::kSobol,
                          DesignType::kGrid})
    if (name == design_type_name(type)) return type;
  if (name == "lhs") return DesignType::kLatinHypercube;  // the alias every study type takes
  throw std::invalid_argument("unknown design type '" + name +
                              "'; valid: monte_carlo, latin_hypercube (or lhs), sobol, grid");
}

int sobol_max_dimensions() {
  return static_cast<int>(boost::random::detail::qrng_tables::sobol::max_dimension);
}

DesignMatrix unit_design(DesignType type, int samples, int dimensions, std::uint64_t seed,
                         const std::atomic<bool>* stop) {
  check_size(samples, dimensions);
  switch (type) {
    case DesignType::kMonteCarlo: return monte_carlo(samples, dimensions, seed, stop);
    case DesignType::kLatinHypercube: return latin_hypercube(samples, dimensions, seed, stop);
    case DesignType::kSobol: return sobol(samples, dimensions, seed, stop);
    case DesignType::kGrid: break;
  }
  throw std::invalid_argument(std::string("unit_design: design type '") + design_type_name(type) +
                              "' is not a random design (use unit_grid for a grid)");
}

DesignMatrix unit_grid(const std::vector<int>& levels) {
  if (levels.empty()) throw std::invalid_argument("unit_grid: no axes");
  long long total = 1;
  for (std::size_t j = 0; j < levels.size(); ++j) {
    if (levels[j] < 1)
      throw std::invalid_argument("unit_grid: axis " + std::to_string(j) + " has " +
                                  std::to_string(levels[j]) + " levels (needs >= 1)");
    total *= levels[j];
    if (total > INT_MAX)
      throw std::invalid_argument("unit_grid: the full factorial has more than " +
                                  std::to_string(INT_MAX) + " points");
  }
  const int dimensions = static_cast<int>(levels.size());
  DesignMatrix u(static_cast<Eigen::Index>(total), dimensions);
  for (Eigen::Index row = 0; row < u.rows(); ++row) {
    long long rest = row;
    for (int j = dimensions - 1; j >= 0; --j) {
      const int k = static_cast<int>(rest % levels[j]);
      rest /= levels[j];
      u(row, j) = levels[j] == 1 ? 0.5 : static_cast<double>(k) / (levels[j] - 1);
    }
  }
  return u;
}

DesignMatrix map_to_distributions(const DesignMatrix& unit,
                                  const std::vector<Distribution>& distributions) {
  if (static_cast<std::size_t>(unit.cols()) != distributions.size())
    throw std::invalid_argument("map_to_distributions: the design has " +
                                std::to_string(unit.cols()) + " columns but " +
                                std::to_string(distributions.size()) + " distributions");
  for (std::size_t j = 0; j < distributions.size(); ++j) {
    std::string why;
    if (!distributions[j].IsValid(&why))
      throw std::invalid_argument("map_to_distributions: distribution " + std::to_string(j) +
                                  " is invalid: " + why);
  }
  DesignMatrix x(unit.rows(), unit.cols());
  for (Eigen::Index i = 0; i < unit.rows(); ++i)
    for (Eigen::Index j = 0; j < unit.cols(); ++j)
      x(i, j) = distributions[static_cast<std::size_t>(j)].quantile(unit(i, j));
  return x;
}

double centered_l2_discrepancy(const DesignMatrix& unit) {
  const Eigen::Index n = unit.rows(), d = unit.cols();
  if (n < 1 || d < 1) throw std::invalid_argument("centered_l2_discrepancy: empty design");
  const Eigen::ArrayXXd centred = (unit.array() - 0.5).abs();  // |x_ik - 1/2|
  double single = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    double product = 1.0;
    for (Eigen::Index k = 0; k < d; ++k) {
      const double c = centred(i, k);
      product *= 1.0 + 0.5 * c - 0.5 * c * c;
    }
    single += product;
  }
  // The double sum is symmetric: the diagonal once, each pair twice.
  double pairs = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j <= i; ++j) {
      double product = 1.0;
      for (Eigen::Index k = 0; k < d; ++k)
        product *= 1.0 + 0.5 * centred(i, k) + 0.5 * centred(j, k) -
                   0.5 * std::abs(unit(i, k) - unit(j, k));
      pairs += i == j ? product : 2.0 * product;
    }
  }
  const double nn = static_cast<double>(n);
  const double squared = std::pow(13.0 / 12.0, static_cast<double>(d)) - 2.0 / nn * single +
                         pairs / (nn * nn);
  return std::sqrt(std::max(0.0, squared));
}

std::vector<double> linear_grid(double min, double max, int n) {
  if (n < 1) throw std::invalid_argument("a grid needs at least one point");
  std::vector<double> v(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) v[i] = n == 1 ? min : min + (max - min) * i / (n - 1);
  return v;
}

std::vector<double> log_grid(double min, double max, int n) {
  if (!(min > 0.0 && max > 0.0)) throw std::invalid_argument("a log grid needs positive bounds");
  std::vector<double> v = linear_grid(std::log10(min), std::log10(max), n);
  for (double& x : v) x = std::pow(10.0, x);
  if (n > 1) {
    v.front() = min;
    v.back() = max;
  }
  return v;
}

}  // namespace rover::study
