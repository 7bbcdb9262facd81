// Speed of the terrain queries made inside the wheel-contact search
// (core/terrain.hpp): height, and height + gradient, on the obstacle grid.
#include <benchmark/benchmark.h>

#include "core/obstacle.hpp"
#include "core/terrain.hpp"

namespace {

const rover::Terrain& obstacle_terrain() {
  static const rover::Terrain terrain = rover::Terrain::from_grid(rover::trapezoid_obstacle_grid({}));
  return terrain;
}

// Points sweeping a wheel rim across the ramp, the top and the ground.
template <class Query>
void sweep(benchmark::State& state, Query query) {
  const rover::Terrain& t = obstacle_terrain();
  double x = 1.3, y = -0.2215, acc = 0.0;
  for (auto _ : state) {
    acc += query(t, x, y);
    x += 0.000317;
    if (x > 2.3) x = 1.3;
  }
  benchmark::DoNotOptimize(acc);
  state.SetItemsProcessed(state.iterations());
}

void BM_TerrainHeight(benchmark::State& state) {
  sweep(state, [](const rover::Terrain& t, double x, double y) { return t.height(x, y); });
}
void BM_TerrainSample(benchmark::State& state) {
  sweep(state, [](const rover::Terrain& t, double x, double y) {
    const rover::TerrainSample s = t.sample(x, y);
    return s.height_m + s.gradient.x();
  });
}
void BM_TerrainNormal(benchmark::State& state) {
  sweep(state, [](const rover::Terrain& t, double x, double y) { return t.normal(x, y).z(); });
}

BENCHMARK(BM_TerrainHeight);
BENCHMARK(BM_TerrainSample);
BENCHMARK(BM_TerrainNormal);

}  // namespace

BENCHMARK_MAIN();
