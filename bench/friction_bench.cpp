// Makkar friction (core/friction.hpp) on the contact hot path, and the cost
// of one friction synthesis (core/friction_synthesis.hpp).
#include <benchmark/benchmark.h>

#include "core/friction_synthesis.hpp"

namespace {

void BM_MakkarMu(benchmark::State& state) {
  const rover::FrictionParameters p;
  double v = 1e-4;
  for (auto _ : state) {
    benchmark::DoNotOptimize(rover::makkar_mu(v, p.gammas));
    v = v < 0.02 ? v * 1.01 : 1e-4;
  }
}
BENCHMARK(BM_MakkarMu);

void BM_SynthesizeFriction(benchmark::State& state) {
  const rover::FrictionParameters p;
  for (auto _ : state) benchmark::DoNotOptimize(rover::synthesize_friction(p));
}
BENCHMARK(BM_SynthesizeFriction)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
