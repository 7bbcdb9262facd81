#include "study/design/sampling.hpp"
#include "study/estimators/splitmix64.hpp"

#include <cmath>
#include <stdexcept>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>

namespace rover::study {

std::array<double, kNumSJoints> sample_preloads(const SStructureParameters& s, std::uint64_t seed,
                                                std::uint64_t index, double sd_scale) {
  boost::random::mt19937_64 engine(splitmix64(splitmix64(seed) ^ index));
  boost::random::normal_distribution<double> normal(0.0, 1.0);
  std::array<double, kNumSJoints> m0{};
  for (int j = 0; j < kNumSJoints; ++j)
    m0[j] = s.preload_mean_Nm[j] + sd_scale * s.preload_sd_Nm[j] * normal(engine);
  return m0;
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
