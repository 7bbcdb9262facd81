// Shared fixtures for the model tests: random states and the default model.
#pragma once

#include <random>

#include "core/coordinates.hpp"
#include "core/rover_model.hpp"

namespace rover::testing {

// A random but physically reasonable state: chassis near level, joints within
// +-0.3 rad, speeds of order 1.
inline void random_state(std::mt19937& rng, Coordinates& q, Coordinates& u) {
  std::uniform_real_distribution<double> angle(-0.3, 0.3), pos(-0.5, 0.5), speed(-1.0, 1.0);
  for (int i = 0; i < kNumCoordinates; ++i) {
    q[i] = i < 3 ? pos(rng) : angle(rng);
    u[i] = speed(rng);
  }
  q[coord::z] += 0.3;
}

// The default model, with the ground pushed far below so nothing touches it.
inline RoverModel airborne_model(RoverParameters p = default_rover_parameters()) {
  return make_rover_model(std::move(p), Terrain::flat(-100.0));
}

}  // namespace rover::testing
