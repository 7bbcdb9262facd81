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

}  // namespace rover::study
