// The SplitMix64 finaliser (Steele, Lea and Flood 2014): a bijection of 64-bit
// words with good avalanche. The studies derive every per-sample, per-walker
// and per-dimension seed from it, so that a random stream depends only on
// (seed, index) and not on the number of MPI ranks or the order of runs.
#pragma once

#include <cstdint>

namespace rover::study {

inline constexpr std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace rover::study
