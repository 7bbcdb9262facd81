// The stiff integrator against the explicit reference (docs/model.md
// section 9): the 1 s horizontal drop with dopri5 (rtol 1e-6, atol 1e-9, the
// scenario's settings) and rosenbrock (default_integrator_settings: rtol 1e-5,
// atol 2e-4), side by side, for f = 1e2 .. 1e5 and for the friction speed
// scale v_s (and v_k with it) times 1, 0.1 and 0.01: wall time, right-hand
// sides, steps (rosenbrock: best wall time of three runs), and the RMS
// difference of B_l z between the two. Scaling v_s
// and v_k by s scales the Makkar gammas g2, g3, g5 (and g6) by 1/s exactly
// (friction_synthesis.hpp): mu(v) keeps its shape on a speed axis s times
// shorter, so mu'(0) and the stiffness of the stuck friction grow by 1/s.
// The table also counts the S-joint passages through the preload kink in
// the v_s x 1 runs: the steps rosenbrock adds from f = 1e2 to 1e5 are spent
// on them. With --obstacle it also runs the obstacle scenario at 1 m/s
// against a dopri5 reference at rtol 1e-8 (about a minute); with
// --conditioning it shows how far a 10 nm higher drop moves the reference of
// each drop at f = 1e4 and 1e5 (about 30 s); with --tolerances it shows what
// the Rosenbrock atol buys in accuracy and costs in steps, over six preload
// sets (print_tolerance_sweep(), under a minute). Then the Google Benchmark
// timings of a right-hand side, a Jacobian assembly and the drop.
//
// Run on one quiet core, e.g.
//   taskset -c 0 build/bench/integrator_bench [--obstacle] [--conditioning] [--tolerances]
//                                             [--budget 300] [--no-table]
// The dopri5 run at v_s x 0.01 takes about 1.5 minutes (2.3 million steps).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/equations_of_motion.hpp"
#include "core/force_jacobian.hpp"
#include "core/friction_synthesis.hpp"
#include "core/simulate.hpp"
#include "io/scenario_config.hpp"
#include "study/design/sampling.hpp"
#include "drop_fixture.hpp"

namespace {

using namespace rover;
using rover::bench::drop_model_inputs;
using rover::bench::drop_setup;
using rover::bench::BM_RightHandSideAtRest;
using rover::bench::rest_state;
using rover::bench::rms_mm;

// The model with v_s and v_k scaled by `scale` and the gammas scaled to match.
RoverModel friction_scaled_model(const RoverModel& base, double scale) {
  RoverParameters p = base.parameters;
  p.friction = with_friction_speeds_scaled(p.friction, scale);
  return make_rover_model(p, base.terrain);
}

std::string cell(const Trajectory& tr) {
  char buf[96];
  if (tr.ok())
    std::snprintf(buf, sizeof buf, "%9.4f %9ld %8ld", tr.wall_time_s, tr.rhs_evaluations, tr.steps);
  else
    std::snprintf(buf, sizeof buf, "%9.4f %9ld %8ld*", tr.wall_time_s, tr.rhs_evaluations, tr.steps);
  return buf;
}

// How often the S-joints pass through the preload kink: |b| goes from beyond
// 1/f on one side to beyond 1/f on the other (within |b| < 1/f the torque
// turns by 2 M0 / pi). Counted over every joint of a run sampled densely
// enough to see each bounce.
int kink_traversals(const Trajectory& tr, double sharpness_f) {
  int count = 0;
  for (int leg = 0; leg < kNumLegs; ++leg)
    for (int i = 0; i < 2; ++i) {
      const int c = coord::s_joint(leg, i);
      int side = 0;  // -1 below -1/f, +1 above +1/f, 0 not yet out of the kink
      for (Eigen::Index k = 0; k < tr.q.rows(); ++k) {
        const double scaled = tr.q(k, c) * sharpness_f;
        const int now = scaled > 1.0 ? 1 : scaled < -1.0 ? -1 : 0;
        if (now != 0 && side != 0 && now != side) ++count;
        if (now != 0) side = now;
      }
    }
  return count;
}

// The kink traversals of the drop's dopri5 run at the scenario's rtol, sampled
// at 100 kHz (the bounces of a joint at f = 1e5 are a few kHz).
int drop_kink_traversals(const RoverModel& model, const ModelInputs& inputs) {
  Scenario dense = drop_setup().scenario;
  dense.output_rate_hz = 1e5;
  return kink_traversals(simulate(model, dense, inputs), inputs.sharpness_f);
}

void print_drop_table(double budget_s) {
  const io::ScenarioSetup& setup = drop_setup();
  struct Row {
    double f, vs_scale;
  };
  const Row rows[] = {{1e2, 1.0}, {1e3, 1.0}, {1e4, 1.0}, {1e5, 1.0}, {1e4, 0.1}, {1e4, 0.01}};
  std::printf("Horizontal drop, 1 s (configs/scenarios/drop_horizontal.json); wall [s], right-hand sides, steps\n");
  std::printf("dopri5: rtol %.0e atol %.0e; rosenbrock: rtol %.0e atol %.0e (Jacobian assemblies counted as right-hand sides)\n",
              setup.scenario.integrator.relative_tolerance, setup.scenario.integrator.absolute_tolerance,
              default_integrator_settings(IntegratorMethod::kRosenbrockW).relative_tolerance,
              default_integrator_settings(IntegratorMethod::kRosenbrockW).absolute_tolerance);
  std::printf("%8s %6s | %28s | %28s | %7s %7s | %10s | %s\n", "f", "v_s x", "dopri5  wall       rhs    steps",
              "rosenbrock wall     rhs    steps", "speedup", "rhs", "traversals", "B_l z RMS diff [mm]");
  long soft_steps = 0;  // rosenbrock at the first row, f = 1e2
  for (const Row& r : rows) {
    const RoverModel model = friction_scaled_model(setup.model, r.vs_scale);
    ModelInputs inputs = setup.inputs;
    inputs.sharpness_f = r.f;
    Scenario explicit_run = setup.scenario;
    explicit_run.wall_time_budget_s = budget_s;
    Scenario stiff_run = explicit_run;
    stiff_run.integrator = default_integrator_settings(IntegratorMethod::kRosenbrockW);
    // Best of three: the run takes milliseconds, and the first one of the
    // program also pays for cold caches.
    Trajectory ros = simulate(model, stiff_run, inputs);
    for (int repeat = 0; repeat < 2; ++repeat) {
      Trajectory again = simulate(model, stiff_run, inputs);
      if (again.wall_time_s < ros.wall_time_s) ros = std::move(again);
    }
    const Trajectory dp = simulate(model, explicit_run, inputs);
    // The traversals need a second dopri5 run; skipped where that is slow.
    const int traversals = r.vs_scale == 1.0 ? drop_kink_traversals(model, inputs) : -1;
    if (soft_steps == 0) soft_steps = ros.steps;
    std::printf("%8.0e %6.2f | %s | %s | %7.1f %7.1f | %10s | %.4f%s\n", r.f, r.vs_scale, cell(dp).c_str(),
                cell(ros).c_str(), dp.wall_time_s / ros.wall_time_s,
                static_cast<double>(dp.rhs_evaluations) / static_cast<double>(ros.rhs_evaluations),
                traversals < 0 ? "-" : std::to_string(traversals).c_str(), rms_mm(ros.B_l_z, dp.B_l_z),
                dp.ok() && ros.ok() ? "" : " (over the common samples)");
    if (traversals > 0)
      std::printf("%17s rosenbrock steps beyond those at f = %.0e: %.1f per traversal\n", "", rows[0].f,
                  static_cast<double>(ros.steps - soft_steps) / traversals);
    std::fflush(stdout);
  }
  std::printf("* = stopped (wall-time budget); its counts are up to the stop.\n");
  std::printf("traversals: S-joint passages through the preload kink, |b| from beyond 1/f on one side to\n"
              "beyond 1/f on the other, in the dopri5 run sampled at 100 kHz (v_s x 1 rows only).\n\n");
}

void print_obstacle_comparison() {
  const io::ScenarioSetup setup = io::load_scenario(ROVER_SOURCE_DIR "/configs/scenarios/obstacle_v1.json");
  Scenario reference = setup.scenario;
  reference.integrator.relative_tolerance = 1e-8;
  reference.integrator.absolute_tolerance = 1e-11;
  Scenario stiff = setup.scenario;
  stiff.integrator = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  const Trajectory ref = simulate(setup.model, reference, setup.inputs);
  const Trajectory dp = simulate(setup.model, setup.scenario, setup.inputs);
  const Trajectory ros = simulate(setup.model, stiff, setup.inputs);
  std::printf("Obstacle at 1 m/s, %.3f s (configs/scenarios/obstacle_v1.json); wall [s], right-hand sides, steps\n",
              setup.scenario.duration_s);
  std::printf("  dopri5 rtol 1e-8 (reference) %s\n", cell(ref).c_str());
  std::printf("  dopri5 rtol 1e-6             %s   B_l z RMS vs reference %.4f mm\n", cell(dp).c_str(),
              rms_mm(dp.B_l_z, ref.B_l_z));
  std::printf("  rosenbrock                   %s   B_l z RMS vs reference %.4f mm (target < 0.5 mm)\n\n",
              cell(ros).c_str(), rms_mm(ros.B_l_z, ref.B_l_z));
}

// How well the drops are determined: the dopri5 reference (rtol 1e-8) against
// the same run dropped from 10 nm higher, against dopri5 at the scenario's
// rtol 1e-6 and against rosenbrock, for f = 1e4 and 1e5. A run whose
// reference moves by tens of micrometres under a 10 nm change of the drop
// height cannot be matched more closely than that by any integrator.
void print_conditioning() {
  std::printf("Conditioning of the drops (B_l z RMS against dopri5 rtol 1e-8 atol 1e-11, mm)\n");
  std::printf("%-16s %6s | %14s | %14s | %14s\n", "scenario", "f", "10 nm higher", "dopri5 1e-6", "rosenbrock");
  for (const char* name : {"drop_horizontal", "drop_skewed"}) {
    const io::ScenarioSetup setup =
        io::load_scenario(std::string(ROVER_SOURCE_DIR "/configs/scenarios/") + name + ".json");
    for (const double f : {1e4, 1e5}) {
      ModelInputs inputs = setup.inputs;
      inputs.sharpness_f = f;
      Scenario reference = setup.scenario;
      reference.integrator.relative_tolerance = 1e-8;
      reference.integrator.absolute_tolerance = 1e-11;
      Scenario higher = reference;
      higher.initial_q[coord::z] += 1e-8;
      Scenario stiff = setup.scenario;
      stiff.integrator = default_integrator_settings(IntegratorMethod::kRosenbrockW);
      const Trajectory ref = simulate(setup.model, reference, inputs);
      std::printf("%-16s %6.0e | %14.4f | %14.4f | %14.4f\n", name, f,
                  rms_mm(simulate(setup.model, higher, inputs).B_l_z, ref.B_l_z),
                  rms_mm(simulate(setup.model, setup.scenario, inputs).B_l_z, ref.B_l_z),
                  rms_mm(simulate(setup.model, stiff, inputs).B_l_z, ref.B_l_z));
      std::fflush(stdout);
    }
  }
  std::printf("\n");
}

// The preload sets of the tolerance sweep: the means of docs/model.md Table 1 and
// the first `draws` Monte Carlo samples of seed 1 (study::sample_preloads).
std::vector<ModelInputs> preload_sets(const ModelInputs& nominal, const RoverParameters& p,
                                           int draws) {
  std::vector<ModelInputs> sets{nominal};
  for (int k = 0; k < draws; ++k) {
    sets.push_back(nominal);
    sets.back().preload_Nm = study::sample_preloads(p.s_structure, 1, static_cast<std::uint64_t>(k));
  }
  return sets;
}

// What the Rosenbrock atol buys: for atol 1e-4 .. 1e-3 (rtol at its default),
// the largest B_l z RMS difference from dopri5 at rtol 1e-8 over six preload
// sets, for both drops at f = 1e2, 1e4 and 1e5, and the steps and wall time
// summed over the sets; then the horizontal drop's f = 1e5 / f = 1e2 ratios.
// The ratio and the accuracy at f = 1e5 pull against each other.
void print_tolerance_sweep() {
  const double atols[] = {1e-4, 2e-4, 5e-4, 1e-3};
  const double fs[] = {1e2, 1e4, 1e5};
  struct Reference {
    std::string drop;
    ModelInputs inputs;
    std::vector<double> B_l_z;
  };
  std::vector<io::ScenarioSetup> setups;
  std::vector<Reference> references;  // drop-major, then f, then preload set
  for (const char* name : {"drop_horizontal", "drop_skewed"}) {
    setups.push_back(io::load_scenario(std::string(ROVER_SOURCE_DIR "/configs/scenarios/") + name + ".json"));
    const io::ScenarioSetup& setup = setups.back();
    Scenario reference = setup.scenario;
    reference.integrator.relative_tolerance = 1e-8;
    reference.integrator.absolute_tolerance = 1e-11;
    for (const double f : fs) {
      ModelInputs nominal = setup.inputs;
      nominal.sharpness_f = f;
      for (const ModelInputs& in : preload_sets(nominal, setup.model.parameters, 5))
        references.push_back({name, in, simulate(setup.model, reference, in).B_l_z});
    }
  }
  const std::size_t per_drop = references.size() / setups.size(), per_f = per_drop / std::size(fs);
  const IntegratorSettings defaults = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  std::printf("Rosenbrock tolerance sweep (rtol %.0e): max B_l z RMS against dopri5 rtol 1e-8 over %zu preload\n"
              "sets [mm]; steps and wall [s] summed over the sets; f = 1e5 / f = 1e2 ratios of the horizontal drop\n",
              defaults.relative_tolerance, per_f);
  std::printf("%8s | %-16s %8s %8s %8s | %8s %8s %8s | %8s %8s | %11s %10s\n", "atol", "drop", "max 1e2", "max 1e4",
              "max 1e5", "steps1e2", "steps1e4", "steps1e5", "wall 1e2", "wall 1e5", "step ratio", "wall ratio");
  for (const double atol : atols) {
    for (std::size_t d = 0; d < setups.size(); ++d) {
      Scenario stiff = setups[d].scenario;
      stiff.integrator = defaults;
      stiff.integrator.absolute_tolerance = atol;
      double worst[std::size(fs)] = {}, wall[std::size(fs)] = {};
      long steps[std::size(fs)] = {};
      for (std::size_t i = 0; i < per_drop; ++i) {
        const Reference& r = references[d * per_drop + i];
        const Trajectory tr = simulate(setups[d].model, stiff, r.inputs);
        const std::size_t fi = i / per_f;
        worst[fi] = std::max(worst[fi], tr.ok() ? rms_mm(tr.B_l_z, r.B_l_z) : INFINITY);
        steps[fi] += tr.steps;
        wall[fi] += tr.wall_time_s;
      }
      std::printf("%8.0e | %-16s %8.3f %8.3f %8.3f | %8ld %8ld %8ld | %8.3f %8.3f | %11.2f %10.2f\n", atol,
                  references[d * per_drop].drop.c_str(), worst[0], worst[1], worst[2], steps[0], steps[1], steps[2],
                  wall[0], wall[2], static_cast<double>(steps[2]) / static_cast<double>(steps[0]), wall[2] / wall[0]);
      std::fflush(stdout);
    }
  }
  std::printf("\n");
}

// What the integrator adds per step to its right-hand sides: D and K.
void BM_StiffForceJacobian(benchmark::State& state) {
  const io::ScenarioSetup& s = drop_setup();
  const ModelInputs in = drop_model_inputs();
  const StateVector x = rest_state();
  const Coordinates q = x.head<kNumCoordinates>(), u = x.tail<kNumCoordinates>();
  DynamicsWorkspace workspace;
  compute_kinematics(s.model, workspace, q, u);
  compute_contacts(s.model, workspace);
  for (auto _ : state) benchmark::DoNotOptimize(stiff_force_jacobian(s.model, workspace, in, q, u));
}

void BM_DropHorizontal1s(benchmark::State& state) {
  const io::ScenarioSetup& s = drop_setup();
  Scenario scenario = s.scenario;
  const auto method = static_cast<IntegratorMethod>(state.range(0));
  if (method != IntegratorMethod::kDormandPrince45) scenario.integrator = default_integrator_settings(method);
  Trajectory tr;
  for (auto _ : state) {
    tr = simulate(s.model, scenario, s.inputs);
    if (!tr.ok()) state.SkipWithError(tr.message.c_str());
  }
  state.SetLabel(integrator_name(method));
  state.counters["rhs_evaluations"] = static_cast<double>(tr.rhs_evaluations);
  state.counters["steps"] = static_cast<double>(tr.steps);
}

BENCHMARK(BM_RightHandSideAtRest);
BENCHMARK(BM_StiffForceJacobian);
BENCHMARK(BM_DropHorizontal1s)
    ->Unit(benchmark::kMillisecond)
    ->Arg(static_cast<int>(IntegratorMethod::kDormandPrince45))
    ->Iterations(1);
BENCHMARK(BM_DropHorizontal1s)
    ->Unit(benchmark::kMillisecond)
    ->Arg(static_cast<int>(IntegratorMethod::kRosenbrockW))
    ->Iterations(20);

}  // namespace

int main(int argc, char** argv) {
  bool table = true, obstacle = false, conditioning = false, tolerances = false;
  double budget_s = 600.0;
  std::vector<char*> rest{argv[0]};
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--no-table") == 0) {
      table = false;
    } else if (std::strcmp(argv[i], "--obstacle") == 0) {
      obstacle = true;
    } else if (std::strcmp(argv[i], "--conditioning") == 0) {
      conditioning = true;
    } else if (std::strcmp(argv[i], "--tolerances") == 0) {
      tolerances = true;
    } else if (std::strcmp(argv[i], "--budget") == 0 && i + 1 < argc) {
      budget_s = std::stod(argv[++i]);
    } else {
      rest.push_back(argv[i]);
    }
  }
  if (table) print_drop_table(budget_s);
  if (obstacle) print_obstacle_comparison();
  if (conditioning) print_conditioning();
  if (tolerances) print_tolerance_sweep();
  int bench_argc = static_cast<int>(rest.size());
  benchmark::Initialize(&bench_argc, rest.data());
  if (benchmark::ReportUnrecognizedArguments(bench_argc, rest.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
