// Shared by the benchmarks: the 1 s horizontal drop of docs/model.md §7
// (configs/scenarios/drop_horizontal.json), the rover at rest at its end, and
// the benchmark of one right-hand side there.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/equations_of_motion.hpp"
#include "core/simulate.hpp"
#include "io/scenario_config.hpp"

namespace rover::bench {

inline const io::ScenarioSetup& drop_setup() {
  static const io::ScenarioSetup s =
      io::load_scenario(ROVER_SOURCE_DIR "/configs/scenarios/drop_horizontal.json");
  return s;
}

// The state at the end of the drop, simulated once with the scenario's settings.
inline const StateVector& rest_state() {
  static const StateVector x = [] {
    const io::ScenarioSetup& s = drop_setup();
    const Trajectory tr = simulate(s.model, s.scenario, s.inputs);
    StateVector r;
    r << tr.q.bottomRows<1>().transpose(), tr.u.bottomRows<1>().transpose();
    return r;
  }();
  return x;
}

inline ModelInputs drop_model_inputs() {
  const io::ScenarioSetup& s = drop_setup();
  return model_inputs_for(s.scenario, s.inputs);
}

// RMS difference of two sampled curves in mm (of metres), over their common
// samples; NaN if there are none.
inline double rms_mm(const std::vector<double>& a, const std::vector<double>& b) {
  const std::size_t n = std::min(a.size(), b.size());
  if (n == 0) return NAN;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return 1e3 * std::sqrt(sum / static_cast<double>(n));
}

// One right-hand side of the rover at rest on its wheels (both
// simulate_bench and integrator_bench report it, as the unit of their costs).
inline void BM_RightHandSideAtRest(benchmark::State& state) {
  const io::ScenarioSetup& s = drop_setup();
  const ModelInputs in = drop_model_inputs();
  StateVector x = rest_state();
  DynamicsWorkspace workspace;
  for (auto _ : state) {
    benchmark::DoNotOptimize(x);
    benchmark::DoNotOptimize(state_derivative(s.model, workspace, in, x));
  }
}

}  // namespace rover::bench
