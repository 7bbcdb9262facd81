// Shared fixtures for the model tests: random states, the default model and
// sampled height grids.
#pragma once

#include <array>
#include <random>

#include "core/coordinates.hpp"
#include "core/rover_model.hpp"
#include "core/terrain.hpp"
#include "core/terrain_interpolation.hpp"

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

// Whether coordinate i is an ancestor of j or j of i on the coordinate tree
// `parent` (KinematicTree::coordinate_parent): where M and the stiff force
// Jacobians may be non-zero.
inline bool coordinates_related(int i, int j, const std::array<int, kNumCoordinates>& parent) {
  for (int k = i; k >= 0; k = parent[k])
    if (k == j) return true;
  for (int k = j; k >= 0; k = parent[k])
    if (k == i) return true;
  return false;
}

// A height grid sampling h(x, y) at its nodes.
template <class Height>
HeightGrid sampled_grid(double x0, double y0, double dx, double dy, int nx, int ny, Height h) {
  HeightGrid g = grid_with_heights(GridGeometry{x0, y0, dx, dy, nx, ny}, {});
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) g.heights_m.push_back(h(g.node_x(ix), g.node_y(iy)));
  return g;
}

}  // namespace rover::testing
