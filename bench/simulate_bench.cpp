// Speed of simulate() (core/simulate.hpp; docs/model.md §7–9), single
// threaded: the 1 s horizontal drop at default settings (Dormand-Prince,
// rtol 1e-6, atol 1e-9) with its right-hand-side evaluations and steps, one
// right-hand-side evaluation, and wall time against the S-structure sharpness
// f. After the benchmarks it prints what limits the step size: the mean step
// of the adaptive integrator with the rover at rest against the explicit
// stability bound |h lambda| <= 3.3 (Dormand-Prince; 2.8 for RK4) for the
// fastest eigenvalue of the linearised right-hand side, and the friction
// estimate of that eigenvalue, lambda ~ -mu'(0) F_n / m_eff at each wheel.
//
// Run on one quiet core, e.g. `taskset -c 0 build/bench/simulate_bench`.
#include <algorithm>
#include <cstdio>

#include <Eigen/Eigenvalues>
#include <benchmark/benchmark.h>

#include "core/equations_of_motion.hpp"
#include "core/friction.hpp"
#include "core/simulate.hpp"
#include "io/scenario_config.hpp"
#include "drop_fixture.hpp"

namespace {

using namespace rover;
using rover::bench::drop_model_inputs;
using rover::bench::drop_setup;
using rover::bench::BM_RightHandSideAtRest;
using rover::bench::rest_state;

void report(benchmark::State& state, const Trajectory& tr) {
  state.counters["rhs_evaluations"] = static_cast<double>(tr.rhs_evaluations);
  state.counters["steps"] = static_cast<double>(tr.steps);
  state.counters["min_step_s"] = tr.min_step_s;
  state.counters["max_step_s"] = tr.max_step_s;
  state.counters["rhs_per_s"] =
      benchmark::Counter(static_cast<double>(tr.rhs_evaluations), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_DropHorizontal1s(benchmark::State& state) {
  const io::ScenarioSetup& s = drop_setup();
  Trajectory tr;
  for (auto _ : state) {
    tr = simulate(s.model, s.scenario, s.inputs);
    if (!tr.ok()) state.SkipWithError(tr.message.c_str());
  }
  report(state, tr);
}

void BM_DropHorizontal1sVsF(benchmark::State& state) {
  const io::ScenarioSetup& s = drop_setup();
  ModelInputs in = s.inputs;
  in.sharpness_f = static_cast<double>(state.range(0));
  Trajectory tr;
  for (auto _ : state) {
    tr = simulate(s.model, s.scenario, in);
    if (!tr.ok()) state.SkipWithError(tr.message.c_str());
  }
  report(state, tr);
}

BENCHMARK(BM_DropHorizontal1s)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_DropHorizontal1sVsF)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Arg(100)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(100000);
BENCHMARK(BM_RightHandSideAtRest);

// What limits the step size of the adaptive integrator at rest.
void print_step_size_analysis() {
  const io::ScenarioSetup& s = drop_setup();
  const ModelInputs in = drop_model_inputs();
  const StateVector x = rest_state();

  // Mean step over 0.2 s starting at rest.
  Scenario at_rest = s.scenario;
  at_rest.initial_q = x.head<kNumCoordinates>();
  at_rest.initial_u = x.tail<kNumCoordinates>();
  at_rest.duration_s = 0.2;
  const Trajectory tr = simulate(s.model, at_rest, s.inputs);
  const double mean_step = at_rest.duration_s / static_cast<double>(tr.steps);

  // Fastest eigenvalue of the Jacobian of the right-hand side (central differences).
  Eigen::Matrix<double, kStateSize, kStateSize> J;
  DynamicsWorkspace workspace;
  for (int j = 0; j < kStateSize; ++j) {
    const double h = 1e-7 * std::max(1.0, std::abs(x[j]));
    StateVector xp = x, xm = x;
    xp[j] += h;
    xm[j] -= h;
    J.col(j) = (state_derivative(s.model, workspace, in, xp) - state_derivative(s.model, workspace, in, xm)) / (2.0 * h);
  }
  const Eigen::EigenSolver<Eigen::Matrix<double, kStateSize, kStateSize>> eig(J);
  Eigen::Index fastest = 0;
  eig.eigenvalues().cwiseAbs().maxCoeff(&fastest);
  const std::complex<double> lambda = eig.eigenvalues()[fastest];
  const Eigen::VectorXcd mode = eig.eigenvectors().col(fastest);
  // Coordinates that dominate the mode (its u part, the speeds).
  Eigen::VectorXd weight = mode.tail(kNumCoordinates).cwiseAbs();
  weight /= weight.maxCoeff();

  // Friction estimate: tangential damping mu'(0) F_n at each contact, acting on
  // the effective mass of the contact point along the rolling direction.
  const Coordinates q = x.head<kNumCoordinates>(), u = x.tail<kNumCoordinates>();
  const TreeKinematics kin = forward_kinematics(s.model.tree, q, u);
  const auto contacts = wheel_contacts(s.model, kin);
  const CoordinateMatrix M = mass_matrix(s.model.tree, kin);
  const Eigen::LLT<CoordinateMatrix> llt(M);
  const double slope = makkar_mu_derivative(0.0, s.model.parameters.friction.gammas);
  double friction_lambda = 0.0;
  for (int leg = 0; leg < kNumLegs; ++leg)
    for (int k = 0; k < contacts[leg].count; ++k) {
      const ContactPoint& c = contacts[leg].points[k];
      const auto Jp = point_jacobian(s.model.tree, kin, node::wheel(leg), c.point_m);
      const Eigen::Matrix<double, 1, kNumCoordinates> Jx = Jp.row(0);
      const double mobility = (Jx * llt.solve(Jx.transpose()))(0, 0);  // 1 / m_eff
      friction_lambda = std::max(friction_lambda, slope * c.normal_force_N * mobility);
    }

  std::printf("\nStep size at rest (horizontal drop, t = 1 s; dopri5 rtol %.0e atol %.0e):\n",
              s.scenario.integrator.relative_tolerance, s.scenario.integrator.absolute_tolerance);
  std::printf("  mean step over 0.2 s at rest       h = %.3e s (%ld steps, %ld right-hand sides)\n", mean_step,
              tr.steps, tr.rhs_evaluations);
  std::printf("  fastest eigenvalue of d(dx/dt)/dx  lambda = %.4g %+.4gi 1/s\n", lambda.real(), lambda.imag());
  std::printf("    dopri5 bound 3.3/|lambda| = %.3e s, RK4 bound 2.8/|lambda| = %.3e s, h |lambda| = %.2f\n",
              3.3 / std::abs(lambda), 2.8 / std::abs(lambda), mean_step * std::abs(lambda));
  std::printf("    mode speeds (|u_i| / max > 0.1):");
  for (int i = 0; i < kNumCoordinates; ++i)
    if (weight[i] > 0.1) std::printf(" %s %.2f", kCoordinateNames[i], weight[i]);
  std::printf("\n  friction estimate mu'(0) F_n / m_eff = %.4g 1/s (mu'(0) = %.1f s/m): 2.8/lambda = %.3e s\n",
              friction_lambda, slope, 2.8 / friction_lambda);
  const bool stability_limited = mean_step * std::abs(lambda) > 1.0;
  std::printf("  => the step at rest is limited by %s\n",
              stability_limited ? "explicit stability of the stiff stick-slip friction mode (h |lambda| ~ the "
                                  "stability boundary), not by accuracy"
                                : "accuracy (h |lambda| well inside the stability region)");
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_step_size_analysis();
  return 0;
}
