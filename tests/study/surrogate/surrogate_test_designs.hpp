// Designs for the surrogate tests. The test executable links only the
// surrogate and estimator libraries (not study/design, which needs rover_core),
// so it draws its own Latin hypercubes (McKay, Beckman & Conover 1979) and
// Monte Carlo points from the SplitMix64 hash.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "study/estimators/design_matrix.hpp"
#include "study/estimators/distributions.hpp"
#include "study/estimators/splitmix64.hpp"

namespace rover::study::testing {

// A uniform number in (0, 1) from (seed, i).
inline double hashed_uniform(std::uint64_t seed, std::uint64_t i) {
  constexpr double kTwoToMinus53 = 1.0 / 9007199254740992.0;
  return (static_cast<double>(splitmix64(seed * 0x9E3779B97F4A7C15ull + i) >> 11) + 0.5) *
         kTwoToMinus53;
}

inline DesignMatrix latin_hypercube(int n, int d, std::uint64_t seed) {
  DesignMatrix u(n, d);
  std::uint64_t counter = 0;
  for (int j = 0; j < d; ++j) {
    std::vector<int> strata(n);
    std::iota(strata.begin(), strata.end(), 0);
    for (int k = n - 1; k > 0; --k) {  // Fisher-Yates
      const int pick = static_cast<int>(hashed_uniform(seed, counter++) * (k + 1));
      std::swap(strata[k], strata[std::min(pick, k)]);
    }
    for (int i = 0; i < n; ++i) u(i, j) = (strata[i] + hashed_uniform(seed, counter++)) / n;
  }
  return u;
}

inline DesignMatrix monte_carlo(int n, int d, std::uint64_t seed) {
  DesignMatrix u(n, d);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < d; ++j) u(i, j) = hashed_uniform(seed, static_cast<std::uint64_t>(i) * d + j);
  return u;
}

inline DesignMatrix to_inputs(const DesignMatrix& u, const std::vector<Distribution>& inputs) {
  DesignMatrix x(u.rows(), u.cols());
  for (Eigen::Index i = 0; i < u.rows(); ++i)
    for (Eigen::Index j = 0; j < u.cols(); ++j) x(i, j) = inputs[j].quantile(u(i, j));
  return x;
}

}  // namespace rover::study::testing
