// Preload draws for the Monte Carlo (docs/model.md section 5,
// M0 ~ Normal(mean, sd)).
//
// Sample i's draws depend only on (seed, i): its own Boost.Random engine is
// seeded from a SplitMix64 hash of the pair, so a study gives bit-identical
// samples whatever the number of MPI ranks and the order the samples run in.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/rover_parameters.hpp"

namespace rover::study {

// The eight preloads of sample `index`: mean + sd_scale * sd * N(0, 1) each.
std::array<double, kNumSJoints> sample_preloads(const SStructureParameters& s_structure,
                                                std::uint64_t seed, std::uint64_t index,
                                                double sd_scale = 1.0);

}  // namespace rover::study
