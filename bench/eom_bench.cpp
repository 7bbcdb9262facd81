// Speed of the equations of motion (core/equations_of_motion.hpp; docs/model.md
// section 2): one full evaluation of M and F, the right-hand side
// state_derivative on flat ground and on the obstacle grid with a wheel on the
// ramp, and its parts: forward kinematics, the mass matrix, the LLT solve.
#include <cmath>

#include <Eigen/Cholesky>
#include <benchmark/benchmark.h>

#include "core/articulated_body.hpp"
#include "core/branch_induced_llt.hpp"
#include "core/equations_of_motion.hpp"
#include "io/rover_config.hpp"
#include "io/terrain_json.hpp"

namespace {

using namespace rover;

const RoverParameters& parameters() {
  static const RoverParameters p = io::load_rover_parameters(ROVER_SOURCE_DIR "/configs/rover.json");
  return p;
}
const RoverModel& flat_model() {
  static const RoverModel m = make_rover_model(parameters());
  return m;
}
const RoverModel& obstacle_model() {
  static const RoverModel m =
      make_rover_model(parameters(), io::load_terrain(ROVER_SOURCE_DIR "/configs/terrains/obstacle.json"));
  return m;
}

// Standing on flat ground (every wheel 2 mm in), moving and slipping a little.
StateVector flat_state() {
  Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
  q[coord::z] = 0.2285 - 0.002;
  q[coord::pitch] = 0.01;
  q[coord::s_joint(0, 0)] = 0.003;
  u[coord::x] = 0.3;
  for (int leg = 0; leg < kNumLegs; ++leg) u[coord::spin(leg)] = 0.29 / 0.085;
  StateVector x;
  x << q, u;
  return x;
}

// The front-right wheel 1 mm into the 20 deg ramp of the obstacle, the others
// above the ground; driving at 1 m/s.
StateVector ramp_state() {
  const double ramp = 20.0 * M_PI / 180.0, R = 0.085, x_wheel = 1.36 + 0.1;
  Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
  q[coord::x] = x_wheel - 0.360;
  q[coord::z] = (R - 0.001) / std::cos(ramp) + (x_wheel - 1.36) * std::tan(ramp) + 0.1435;
  u[coord::x] = 1.0;
  for (int leg = 0; leg < kNumLegs; ++leg) u[coord::spin(leg)] = 1.0 / R;
  StateVector x;
  x << q, u;
  return x;
}

void BM_EvaluateEquationsOfMotion(benchmark::State& state) {
  const RoverModel& model = flat_model();
  const ModelInputs in = nominal_inputs(model.parameters);
  const StateVector x = flat_state();
  const Coordinates q = x.head<kNumCoordinates>(), u = x.tail<kNumCoordinates>();
  DynamicsWorkspace workspace;
  for (auto _ : state) {
    compute_dynamics(model, workspace, in, q, u);
    benchmark::DoNotOptimize(workspace);
  }
}

using StateDerivative = StateVector (*)(const RoverModel&, DynamicsWorkspace&, const ModelInputs&,
                                        const StateVector&);

// du/dt of the flat-ground drop state through one of the two paths.
void time_flat_state_derivative(benchmark::State& state, StateDerivative derivative) {
  const RoverModel& model = flat_model();
  const ModelInputs in = nominal_inputs(model.parameters);
  StateVector x = flat_state();
  DynamicsWorkspace workspace;
  for (auto _ : state) {
    benchmark::DoNotOptimize(x);
    benchmark::DoNotOptimize(derivative(model, workspace, in, x));
  }
}

void BM_StateDerivativeFlat(benchmark::State& state) {
  time_flat_state_derivative(state, &state_derivative);
}

void BM_StateDerivativeObstacleRamp(benchmark::State& state) {
  const RoverModel& model = obstacle_model();
  const ModelInputs in = nominal_inputs(model.parameters);
  StateVector x = ramp_state();
  int contacts = 0;
  {
    const TreeKinematics kin = forward_kinematics(model.tree, x.head<kNumCoordinates>(), x.tail<kNumCoordinates>());
    for (const WheelContacts& w : wheel_contacts(model, kin)) contacts += w.count;
  }
  if (contacts != 1) state.SkipWithError("the ramp state should have exactly one contact");
  DynamicsWorkspace workspace;
  for (auto _ : state) {
    benchmark::DoNotOptimize(x);
    benchmark::DoNotOptimize(state_derivative(model, workspace, in, x));
  }
  state.counters["contacts"] = contacts;
}

void BM_ForwardKinematics(benchmark::State& state) {
  const RoverModel& model = flat_model();
  const StateVector x = flat_state();
  const Coordinates q = x.head<kNumCoordinates>(), u = x.tail<kNumCoordinates>();
  for (auto _ : state) benchmark::DoNotOptimize(forward_kinematics(model.tree, q, u));
}

void BM_MassMatrix(benchmark::State& state) {
  const RoverModel& model = flat_model();
  const StateVector x = flat_state();
  const TreeKinematics kin = forward_kinematics(model.tree, x.head<kNumCoordinates>(), x.tail<kNumCoordinates>());
  for (auto _ : state) benchmark::DoNotOptimize(mass_matrix(model.tree, kin));
}

// M, F and the kinematics at flat_state().
DynamicsWorkspace flat_dynamics() {
  const RoverModel& model = flat_model();
  const StateVector x = flat_state();
  DynamicsWorkspace eom;
  compute_dynamics(model, eom, nominal_inputs(model.parameters), x.head<kNumCoordinates>(),
                   x.tail<kNumCoordinates>());
  return eom;
}

void BM_LltSolve(benchmark::State& state) {
  const DynamicsWorkspace eom = flat_dynamics();
  for (auto _ : state) benchmark::DoNotOptimize(Coordinates(eom.mass_matrix.llt().solve(eom.forcing)));
}

// M^{-1} F two ways: the articulated-body recursion (the Rosenbrock stages),
// and forming M and its block Cholesky (the step ends).
void BM_ArticulatedBodySolve(benchmark::State& state) {
  const RoverModel& model = flat_model();
  const DynamicsWorkspace eom = flat_dynamics();
  for (auto _ : state) benchmark::DoNotOptimize(articulated_body_solve(model.tree, eom.kinematics, eom.forcing));
}

void BM_MassMatrixBlockCholeskySolve(benchmark::State& state) {
  const RoverModel& model = flat_model();
  const DynamicsWorkspace eom = flat_dynamics();
  BranchInducedLLT llt;
  for (auto _ : state) {
    llt.compute(mass_matrix(model.tree, eom.kinematics));
    benchmark::DoNotOptimize(llt.solve(eom.forcing));
  }
}

void BM_StateDerivativeArticulatedFlat(benchmark::State& state) {
  time_flat_state_derivative(state, &state_derivative_articulated);
}

void BM_WheelContactsObstacleRamp(benchmark::State& state) {
  const RoverModel& model = obstacle_model();
  const StateVector x = ramp_state();
  const TreeKinematics kin = forward_kinematics(model.tree, x.head<kNumCoordinates>(), x.tail<kNumCoordinates>());
  for (auto _ : state) benchmark::DoNotOptimize(wheel_contacts(model, kin));
}

BENCHMARK(BM_EvaluateEquationsOfMotion);
BENCHMARK(BM_StateDerivativeFlat);
BENCHMARK(BM_StateDerivativeObstacleRamp);
BENCHMARK(BM_ForwardKinematics);
BENCHMARK(BM_MassMatrix);
BENCHMARK(BM_LltSolve);
BENCHMARK(BM_WheelContactsObstacleRamp);
BENCHMARK(BM_ArticulatedBodySolve);
BENCHMARK(BM_MassMatrixBlockCholeskySolve);
BENCHMARK(BM_StateDerivativeArticulatedFlat);

}  // namespace

BENCHMARK_MAIN();
