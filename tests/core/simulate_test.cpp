// simulate() (core/simulate.cpp, core/integrators.cpp; docs/model.md §7–9)
// on the shipped scenarios: the adaptive and a fine fixed-step integrator
// agree; a dropped rover lands, rebounds and comes to rest in a sensible pose
// carrying its weight; with the wheels held, energy (contact springs included)
// never grows; over the obstacle the right bogie pin rises and comes back, the
// bogies counter-rotate and the heading is kept; runs are deterministic; and
// numerical trouble ends in a status, never a crash or a hang.
#include "core/simulate.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include <gtest/gtest.h>

#include "core/equations_of_motion.hpp"
#include "core/metrics.hpp"
#include "io/scenario_config.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using testing::source_path;

io::ScenarioSetup shipped(const std::string& name) {
  return io::load_scenario(source_path("configs/scenarios/" + name + ".json"));
}

double weight_N(const RoverModel& model) {
  return model.tree.total_mass_kg * model.parameters.gravity_mps2;
}

TEST(Simulate, DormandPrinceAndFineStepRk4Agree) {
  io::ScenarioSetup setup = shipped("drop_horizontal");
  setup.scenario.duration_s = 0.4;  // release, impact, first rebound
  const Trajectory adaptive = simulate(setup.model, setup.scenario, setup.inputs);
  setup.scenario.integrator.method = IntegratorMethod::kRungeKutta4;
  setup.scenario.integrator.fixed_step_s = 5e-6;
  const Trajectory fixed = simulate(setup.model, setup.scenario, setup.inputs);
  ASSERT_TRUE(adaptive.ok()) << adaptive.message;
  ASSERT_TRUE(fixed.ok()) << fixed.message;
  ASSERT_EQ(adaptive.t.size(), 401u);
  ASSERT_EQ(fixed.t, adaptive.t);
  EXPECT_EQ(fixed.steps, 80000);  // 5 us steps dividing the 1 ms output period
  // docs/model.md §9: B_l z within 0.05 mm.
  EXPECT_LT(rms_difference(adaptive.t, adaptive.B_l_z, fixed.t, fixed.B_l_z), 5e-5);
  double worst = 0.0;
  for (std::size_t i = 0; i < adaptive.t.size(); ++i)
    worst = std::max(worst, std::abs(adaptive.B_l_z[i] - fixed.B_l_z[i]));
  EXPECT_LT(worst, 5e-5);
  // The comparison covers the impact, not just free fall.
  EXPECT_GT(adaptive.normal_force_N.maxCoeff(), weight_N(setup.model) / 4);
}

TEST(Simulate, DropLandsReboundsAndComesToRest) {
  const io::ScenarioSetup setup = shipped("drop_horizontal");
  const Trajectory tr = simulate(setup.model, setup.scenario, setup.inputs);
  ASSERT_TRUE(tr.ok()) << tr.message;
  ASSERT_EQ(tr.t.size(), 1001u);
  EXPECT_EQ(tr.t.back(), 1.0);
  const double mg = weight_N(setup.model);

  // Free fall first (no force), then contact forces appear.
  EXPECT_EQ(tr.normal_force_N.row(0).sum(), 0.0);
  Eigen::Index first_contact = -1;
  for (Eigen::Index i = 0; i < tr.normal_force_N.rows() && first_contact < 0; ++i)
    if (tr.normal_force_N.row(i).sum() > 0.0) first_contact = i;
  ASSERT_GT(first_contact, 10);  // released ~5 cm above the ground: ~0.1 s of fall
  // In free fall z follows z0 - g t^2 / 2 (nothing else acts on the whole rover).
  const auto k = static_cast<std::size_t>(first_contact - 1);
  EXPECT_NEAR(tr.q(first_contact - 1, coord::z) - tr.q(0, coord::z),
              -0.5 * setup.model.parameters.gravity_mps2 * tr.t[k] * tr.t[k], 1e-9);

  // Lands: B_l z reaches a minimum, then rebounds to a local maximum above it.
  std::size_t first_min = 0;
  for (std::size_t i = 1; i + 1 < tr.B_l_z.size(); ++i)
    if (tr.B_l_z[i] < tr.B_l_z[i - 1] && tr.B_l_z[i] <= tr.B_l_z[i + 1]) {
      first_min = i;
      break;
    }
  ASSERT_GT(first_min, static_cast<std::size_t>(first_contact));
  std::size_t rebound = 0;
  for (std::size_t i = first_min + 1; i + 1 < tr.B_l_z.size(); ++i)
    if (tr.B_l_z[i] > tr.B_l_z[i - 1] && tr.B_l_z[i] >= tr.B_l_z[i + 1]) {
      rebound = i;
      break;
    }
  ASSERT_GT(rebound, first_min) << "no local maximum after the first minimum";
  EXPECT_GT(tr.B_l_z[rebound] - tr.B_l_z[first_min], 0.005) << "a rebound of at least 5 mm";
  EXPECT_LT(tr.B_l_z[rebound], tr.B_l_z.front()) << "it does not bounce back to the release height";

  // At rest by 1 s: no motion, the wheels carry the weight.
  const Eigen::Index last = tr.q.rows() - 1;
  EXPECT_LT(tr.u.row(last).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_NEAR(tr.normal_force_N.row(last).sum(), mg, 0.01 * mg);
  for (int leg = 0; leg < kNumLegs; ++leg)
    EXPECT_NEAR(tr.normal_force_N(last, leg), mg / 4, 0.2 * mg / 4) << "wheel " << leg + 1;
  // ... in a sensible pose: chassis level, resting on its wheels above the ground.
  const double degree = std::numbers::pi / 180.0;
  EXPECT_LT(std::abs(tr.pitch.back()), 1.0 * degree);
  EXPECT_LT(std::abs(tr.roll.back()), 1.0 * degree);
  EXPECT_GT(tr.G_z.back(), 0.2);                           // wheel bottoms are 0.2285 m below G
  EXPECT_LT(tr.G_z.back(), 0.2285);                        // S-structures and contact compressed
  EXPECT_NEAR(tr.B_l_z.back(), tr.B_r_z.back(), 0.001);    // level side to side
  EXPECT_GT(tr.B_l_z.back(), tr.B_l_z[first_min]);         // rests above its deepest point
}

TEST(Simulate, EnergyNeverGrowsWithTheWheelsHeld) {
  // Horizontal drop on flat ground, w_ref = d_ref = 0. The total energy is
  // the mechanical energy plus the elastic energy k p^(sigma+1)/(sigma+1) of
  // each contact; everything else (contact and joint damping, friction, the
  // holding drives, the one-sided contact) only dissipates.
  io::ScenarioSetup setup = shipped("drop_horizontal");
  setup.scenario.duration_s = 0.6;
  ASSERT_EQ(setup.scenario.wheel_speed_ref_radps, (std::array<double, 4>{}));
  ASSERT_TRUE(setup.model.terrain.is_flat());
  const Trajectory tr = simulate(setup.model, setup.scenario, setup.inputs);
  ASSERT_TRUE(tr.ok()) << tr.message;

  const ModelInputs inputs = model_inputs_for(setup.scenario, setup.inputs);
  const ContactParameters& k = setup.model.parameters.contact;
  std::vector<double> energy;
  double max_contact_energy = 0.0;
  DynamicsWorkspace workspace;
  for (Eigen::Index i = 0; i < tr.q.rows(); ++i) {
    const Coordinates q = tr.q.row(i).transpose(), u = tr.u.row(i).transpose();
    const TreeKinematics kin = forward_kinematics(setup.model.tree, q, u);
    double contact = 0.0;
    for (const WheelContacts& w : wheel_contacts(setup.model, kin))
      for (int c = 0; c < w.count; ++c)
        contact += k.stiffness_k_g * std::pow(w.points[c].penetration_m, k.exponent_sigma + 1.0) /
                   (k.exponent_sigma + 1.0);
    max_contact_energy = std::max(max_contact_energy, contact);
    energy.push_back(mechanical_energy(setup.model, workspace, inputs, q, u) + contact);
  }
  // Tolerance: integration error only (rtol 1e-6; measured increases are at
  // round-off, 1e-14 J). Leaving out the contact springs' energy would show
  // apparent increases of ~7e-4 J, so the check can tell.
  double worst_increase = 0.0;
  std::size_t worst_at = 0;
  for (std::size_t i = 1; i < energy.size(); ++i)
    if (energy[i] - energy[i - 1] > worst_increase) {
      worst_increase = energy[i] - energy[i - 1];
      worst_at = i;
    }
  EXPECT_LT(worst_increase, 1e-6) << "at t = " << tr.t[worst_at];
  EXPECT_LT(energy.back(), energy.front());
  // The check is not vacuous: the contacts stored energy, and much was dissipated.
  EXPECT_GT(max_contact_energy, 0.01);
  EXPECT_GT(energy.front() - energy.back(), 0.5);
}

TEST(Simulate, ObstacleAtOneMetrePerSecond) {
  const io::ScenarioSetup setup = shipped("obstacle_v1");
  const Trajectory tr = simulate(setup.model, setup.scenario, setup.inputs);
  ASSERT_TRUE(tr.ok()) << tr.message;
  ASSERT_EQ(tr.t.size(), 2870u);  // 2.869 s at 1 kHz
  const double obstacle_height = 0.10, degree = std::numbers::pi / 180.0;
  auto index_at = [&](double t) { return static_cast<std::size_t>(std::lround(t * 1000.0)); };

  // Settled on flat ground before the front-right wheel reaches the ramp foot
  // (x = 1.36 m; the wheel is 0.36 + 0.085 m ahead of G): the reference level.
  double level = 0.0;
  for (std::size_t i = index_at(0.5); i <= index_at(0.8); ++i) level += tr.B_r_z[i] / (index_at(0.8) - index_at(0.5) + 1);
  EXPECT_NEAR(tr.B_r_z[index_at(0.5)], tr.B_r_z[index_at(0.8)], 1e-4) << "not settled before the obstacle";

  // The right bogie pin rises by part of the obstacle height: the 0.30 m top is
  // shorter than the 0.72 m wheelbase, so both right wheels are never on top.
  const auto peak = std::max_element(tr.B_r_z.begin(), tr.B_r_z.end());
  const double rise = *peak - level;
  EXPECT_GT(rise, 0.30 * obstacle_height);
  EXPECT_LT(rise, 0.70 * obstacle_height);
  // ... and comes back down once both right wheels are past it.
  EXPECT_NEAR(tr.B_r_z.back(), level, 0.002);
  // The left side stays near its level; its pin moves much less.
  const double left_rise = *std::max_element(tr.B_l_z.begin(), tr.B_l_z.end()) - level;
  EXPECT_LT(left_rise, 0.5 * rise);

  // Bogie angle: nonzero while climbing, with the opposite sign when the rear
  // wheel climbs; the left bogie turns the opposite way relative to the chassis.
  const auto phi = tr.q.col(coord::bogie);
  Eigen::Index front_up, rear_up;
  const double phi_min = phi.minCoeff(&front_up), phi_max = phi.maxCoeff(&rear_up);
  EXPECT_LT(phi_min, -0.02);
  EXPECT_GT(phi_max, 0.02);
  EXPECT_LT(front_up, rear_up) << "the front wheel climbs first";
  for (const Eigen::Index i : {front_up, rear_up}) {
    const Coordinates q = tr.q.row(i).transpose();
    const TreeKinematics kin = forward_kinematics(setup.model.tree, q, Coordinates::Zero());
    const Mat3& chassis = kin.nodes[node::chassis].rotation;
    // Elevation of each bogie's forward axis, in the chassis frame.
    const double right = (chassis.transpose() * kin.nodes[node::bogie_right].rotation)(2, 0);
    const double left = (chassis.transpose() * kin.nodes[node::bogie_left].rotation)(2, 0);
    const double expected_sign = i == front_up ? 1.0 : -1.0;  // the raised wheel's end goes up
    EXPECT_GT(expected_sign * right, 0.02) << "t = " << tr.t[static_cast<std::size_t>(i)];
    EXPECT_LT(expected_sign * left, -0.02) << "t = " << tr.t[static_cast<std::size_t>(i)];
    EXPECT_NEAR(right, -left, 1e-12);
    // The right front (or rear) wheel is the raised one: in the chassis frame it
    // is higher than its bogie partner, while on the left the order is reversed.
    auto z_in_chassis = [&](int leg) {
      return (chassis.transpose() * (kin.nodes[node::wheel(leg)].origin - kin.nodes[node::chassis].origin)).z();
    };
    EXPECT_GT(expected_sign * (z_in_chassis(1) - z_in_chassis(3)), 0.0);  // FR vs RR
    EXPECT_LT(expected_sign * (z_in_chassis(0) - z_in_chassis(2)), 0.0);  // FL vs RL
  }

  // Keeps its heading, drifts little sideways, and really drives the distance.
  EXPECT_LT(tr.q.col(coord::yaw).cwiseAbs().maxCoeff(), 2.0 * degree);
  EXPECT_LT(tr.q.col(coord::y).cwiseAbs().maxCoeff(), 0.04);
  EXPECT_NEAR(tr.q(tr.q.rows() - 1, coord::x), 2.869, 0.05 * 2.869);
}

TEST(Simulate, RunsAreBitIdentical) {
  io::ScenarioSetup setup = shipped("drop_skewed");
  setup.scenario.duration_s = 0.3;
  const Trajectory a = simulate(setup.model, setup.scenario, setup.inputs);
  const Trajectory b = simulate(setup.model, setup.scenario, setup.inputs);
  ASSERT_TRUE(a.ok()) << a.message;
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.q, b.q);
  EXPECT_EQ(a.u, b.u);
  EXPECT_EQ(a.B_l_z, b.B_l_z);
  EXPECT_EQ(a.B_r_z, b.B_r_z);
  EXPECT_EQ(a.G_z, b.G_z);
  EXPECT_EQ(a.pitch, b.pitch);
  EXPECT_EQ(a.roll, b.roll);
  EXPECT_EQ(a.normal_force_N, b.normal_force_N);
  EXPECT_EQ(a.rhs_evaluations, b.rhs_evaluations);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_GT(a.normal_force_N.maxCoeff(), 0.0);  // through an impact
}

// A raised stop flag (a signal's request) ends a run at its next step with
// SimulationStopped, which is neither a result nor a failure status; a flag
// that stays down changes nothing.
TEST(Simulate, AStopFlagEndsTheRunAtItsNextStep) {
  io::ScenarioSetup setup = shipped("drop_horizontal");
  setup.scenario.duration_s = 0.1;
  std::atomic<bool> stop{false};
  SimulationObserver observer;
  observer.stop = &stop;
  const Trajectory unstopped = simulate(setup.model, setup.scenario, setup.inputs, observer);
  ASSERT_TRUE(unstopped.ok()) << unstopped.message;
  EXPECT_EQ(unstopped.B_l_z, simulate(setup.model, setup.scenario, setup.inputs).B_l_z);
  stop = true;
  try {
    (void)simulate(setup.model, setup.scenario, setup.inputs, observer);
    ADD_FAILURE() << "the run ended although its stop flag was up";
  } catch (const SimulationStopped& e) {
    EXPECT_LT(e.t_s, 0.01) << e.what();
    EXPECT_NE(std::string(e.what()).find("stopped on request"), std::string::npos) << e.what();
  }
}

TEST(Simulate, TinyWallTimeBudgetStopsWithAStatus) {
  io::ScenarioSetup setup = shipped("drop_horizontal");
  setup.scenario.wall_time_budget_s = 1e-9;
  const Trajectory tr = simulate(setup.model, setup.scenario, setup.inputs);
  EXPECT_FALSE(tr.ok());
  EXPECT_EQ(tr.status, SimulationStatus::kTimeBudgetExceeded);
  EXPECT_NE(tr.message.find("time budget"), std::string::npos) << tr.message;
  EXPECT_LT(tr.t.size(), 1001u);
  EXPECT_GE(tr.t.size(), 1u);  // the initial state is kept
  // The arrays stay consistent.
  EXPECT_EQ(static_cast<std::size_t>(tr.q.rows()), tr.t.size());
  EXPECT_EQ(tr.B_l_z.size(), tr.t.size());
}

// RunPaceWatch on paces with known projections (duration 1 s unless said).
TEST(RunPaceWatch, AConstantCrawlIsHopelessAfterTheGracePeriodOnly) {
  RunPaceWatch watch(1.0, 3600.0);
  // 1e-6 simulated seconds per wall second: 1e6 s to go.
  EXPECT_FALSE(watch.hopeless(0.5, 0.5e-6));
  EXPECT_FALSE(watch.hopeless(1.0, 1.0e-6));
  EXPECT_FALSE(watch.hopeless(1.9, 1.9e-6));  // inside the grace period
  ASSERT_TRUE(watch.hopeless(2.0, 2.0e-6));
  // Projected: 2 + (1 - 2e-6) / 1e-6 = 1,000,000 s = 277.8 h.
  EXPECT_NE(watch.explanation().find("after 2 s of computing the run reached t = 2e-06 s of 1 s; "
                                     "at this pace it needs ~278 h, beyond the wall-time budget of 1 h"),
            std::string::npos)
      << watch.explanation();
}

TEST(RunPaceWatch, ASlowStartIsForgotten) {
  // 10 s to simulate with a budget of 6 s (hopeless beyond 12 s): nothing
  // happens for 1 s, then 1 simulated second per wall second. The pace since
  // the start (0.5) would project 2 + 9 / 0.5 = 20 s; the recent pace (1)
  // projects 2 + 9 = 11 s, within two budgets.
  RunPaceWatch watch(10.0, 6.0);
  EXPECT_FALSE(watch.hopeless(0.5, 0.0));
  EXPECT_FALSE(watch.hopeless(1.0, 0.0));
  EXPECT_FALSE(watch.hopeless(1.5, 0.5));
  EXPECT_FALSE(watch.hopeless(2.0, 1.0));
  EXPECT_FALSE(watch.hopeless(3.0, 2.0));
  // The same run slows to 0.2 s per s after t = 2 s: over the window from the
  // 2 s mark (t = 1) the pace is 1.2 / 2 = 0.6, projected 4 + 7.8 / 0.6 = 17 s.
  EXPECT_TRUE(watch.hopeless(4.0, 2.2));
}

TEST(RunPaceWatch, ARunThatStopsAdvancingOrNeedsAboutItsBudget) {
  RunPaceWatch stuck(1.0, 3600.0);
  EXPECT_FALSE(stuck.hopeless(1.0, 0.25));
  ASSERT_TRUE(stuck.hopeless(2.5, 0.25));
  EXPECT_NE(stuck.explanation().find("it has not advanced for the last 1.5 s"), std::string::npos)
      << stuck.explanation();
  // Needing 1.5 budgets is left to the budget itself.
  RunPaceWatch close(1.0, 10.0);
  EXPECT_FALSE(close.hopeless(1.0, 1.0 / 15.0));
  EXPECT_FALSE(close.hopeless(2.0, 2.0 / 15.0));  // projected 15 s < 2 x 10 s
  // No budget, no projection.
  RunPaceWatch unlimited(1.0, std::numeric_limits<double>::infinity());
  EXPECT_FALSE(unlimited.hopeless(1.0, 0.0));
  EXPECT_FALSE(unlimited.hopeless(100.0, 0.0));
}

TEST(Simulate, ARunThatCannotFinishWithinItsBudgetStopsAfterSeconds) {
  // Driving at 1e8 m/s: dopri5 crawls through nanosecond steps (hours for the
  // 1 s drop). With a budget of one minute it is stopped once the pace is
  // known, not after the minute. (The margin is wide: the run needs about a
  // hundred budgets on any machine. Against the shipped one-hour budget it
  // would need about two, which a faster machine may bring under the
  // projection's margin, and then only the budget itself stops it.)
  constexpr double kBudget_s = 60.0;
  io::ScenarioSetup setup = shipped("drop_horizontal");
  setup.scenario.wall_time_budget_s = kBudget_s;
  const double wheel_rate = 1e8 / setup.model.parameters.geometry.wheel_radius_m;
  setup.scenario.initial_u[coord::x] = 1e8;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    setup.scenario.wheel_speed_ref_radps[static_cast<std::size_t>(leg)] = wheel_rate;
    setup.scenario.initial_u[coord::spin(leg)] = wheel_rate;
  }
  const Trajectory tr = simulate(setup.model, setup.scenario, setup.inputs);
  EXPECT_EQ(tr.status, SimulationStatus::kTimeBudgetExceeded) << tr.message;
  EXPECT_LT(tr.wall_time_s, 0.5 * kBudget_s);
  EXPECT_GE(tr.wall_time_s, RunPaceWatch::kGraceWall_s);  // wall time >= compute time
  EXPECT_NE(tr.message.find("of computing the run reached t = "), std::string::npos) << tr.message;
  EXPECT_NE(tr.message.find("at this pace it needs ~"), std::string::npos) << tr.message;
  EXPECT_NE(tr.message.find("beyond the wall-time budget of 60 s"), std::string::npos) << tr.message;
  EXPECT_EQ(static_cast<std::size_t>(tr.q.rows()), tr.t.size());
}

TEST(Simulate, ThePaceCheckDoesNotChangeANormalRun) {
  io::ScenarioSetup setup = shipped("drop_horizontal");
  setup.scenario.integrator = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  const Trajectory checked = simulate(setup.model, setup.scenario, setup.inputs);
  setup.scenario.wall_time_budget_s = std::numeric_limits<double>::infinity();  // never projected
  const Trajectory unchecked = simulate(setup.model, setup.scenario, setup.inputs);
  ASSERT_TRUE(checked.ok()) << checked.message;
  ASSERT_TRUE(unchecked.ok()) << unchecked.message;
  EXPECT_EQ(checked.B_l_z, unchecked.B_l_z);
  EXPECT_EQ(checked.q, unchecked.q);
  EXPECT_EQ(checked.steps, unchecked.steps);
  EXPECT_EQ(checked.rhs_evaluations, unchecked.rhs_evaluations);
}

TEST(Simulate, AbsurdInputsFailWithAStatusNotACrashOrHang) {
  // A budget far above the expected time turns a hang into a visible failure.
  const auto start = std::chrono::steady_clock::now();
  {
    // An S-structure 1e8 times too sharp that the integrator may not resolve.
    io::ScenarioSetup setup = shipped("drop_horizontal");
    setup.inputs.sharpness_f = 1e12;
    setup.scenario.integrator.min_step_s = 1e-4;
    setup.scenario.integrator.initial_step_s = 1e-4;
    setup.scenario.wall_time_budget_s = 60.0;
    const Trajectory tr = simulate(setup.model, setup.scenario, setup.inputs);
    EXPECT_EQ(tr.status, SimulationStatus::kStepSizeUnderflow) << tr.message;
    EXPECT_NE(tr.message.find("step"), std::string::npos) << tr.message;
    EXPECT_EQ(static_cast<std::size_t>(tr.q.rows()), tr.t.size());
  }
  {
    // A non-finite initial state.
    io::ScenarioSetup setup = shipped("drop_horizontal");
    setup.scenario.initial_u[coord::roll] = std::nan("");
    setup.scenario.wall_time_budget_s = 60.0;
    const Trajectory tr = simulate(setup.model, setup.scenario, setup.inputs);
    EXPECT_EQ(tr.status, SimulationStatus::kNonFinite) << tr.message;
    EXPECT_NE(tr.message.find("NaN"), std::string::npos) << tr.message;
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30.0);
}

// The drive schedule is compiled against the model that runs it, not the one
// the scenario was loaded with: the same turn on a rover whose steering stops
// at 10 deg cannot be served, and the run says so instead of throwing.
TEST(Simulate, ADriveTheModelCannotServeIsAnInvalidScenario) {
  io::ScenarioSetup setup = shipped("turn_ackermann");
  setup.scenario.duration_s = 0.05;
  ASSERT_FALSE(setup.scenario.drive.segments.empty());
  const Trajectory served = simulate(setup.model, setup.scenario, setup.inputs);
  ASSERT_TRUE(served.ok()) << served.message;
  RoverParameters narrow = setup.model.parameters;
  narrow.steering.limit_rad = 10.0 * std::numbers::pi / 180.0;
  const RoverModel model = make_rover_model(narrow, setup.model.terrain);
  const Trajectory tr = simulate(model, setup.scenario, setup.inputs);
  EXPECT_EQ(tr.status, SimulationStatus::kInvalidScenario);
  EXPECT_NE(tr.message.find("end-stop"), std::string::npos) << tr.message;
  EXPECT_TRUE(tr.t.empty());
  EXPECT_EQ(tr.rhs_evaluations, 0);
}

// Settings that cannot work fail at once with a status, not after a run at
// another step (RK4) or a hang.
TEST(Simulate, InvalidSettingsAreAnInvalidScenario) {
  io::ScenarioSetup setup = shipped("drop_horizontal");
  setup.scenario.integrator = default_integrator_settings(IntegratorMethod::kRungeKutta4);
  setup.scenario.integrator.fixed_step_s = 0.5;  // the output period is 1 ms
  Trajectory tr = simulate(setup.model, setup.scenario, setup.inputs);
  EXPECT_EQ(tr.status, SimulationStatus::kInvalidScenario);
  EXPECT_NE(tr.message.find("fixed_step 0.5 s"), std::string::npos) << tr.message;
  EXPECT_EQ(tr.rhs_evaluations, 0);
  setup.scenario.integrator = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  setup.scenario.integrator.min_step_s = 1e-3;  // above initial_step
  tr = simulate(setup.model, setup.scenario, setup.inputs);
  EXPECT_EQ(tr.status, SimulationStatus::kInvalidScenario);
  EXPECT_NE(tr.message.find("min_step <= initial_step"), std::string::npos) << tr.message;
}

// A run whose steps cannot advance the time stops with its own status: a
// step at round-off of the time (RK4 at 1e-16 s), and steps of 1e-10 s that
// would take 1e10 of them for one second (caught after 1e5 steps).
TEST(Simulate, ACollapsedStepSizeStopsTheRun) {
  io::ScenarioSetup setup = shipped("drop_horizontal");
  setup.scenario.integrator = default_integrator_settings(IntegratorMethod::kRungeKutta4);
  setup.scenario.integrator.fixed_step_s = 1e-16;  // 1e16 steps: refused before the first
  Trajectory tr = simulate(setup.model, setup.scenario, setup.inputs);
  EXPECT_EQ(tr.status, SimulationStatus::kInvalidScenario) << tr.message;
  EXPECT_NE(tr.message.find("a run may take"), std::string::npos) << tr.message;
  EXPECT_EQ(tr.steps, 0);

  setup.scenario.integrator = default_integrator_settings(IntegratorMethod::kDormandPrince45);
  setup.scenario.integrator.initial_step_s = 1e-11;
  setup.scenario.integrator.max_step_s = 1e-10;
  // No budget: on a slow machine the pace check (RunPaceWatch) would come first.
  setup.scenario.wall_time_budget_s = std::numeric_limits<double>::infinity();
  tr = simulate(setup.model, setup.scenario, setup.inputs);
  EXPECT_EQ(tr.status, SimulationStatus::kStepSizeCollapsed) << tr.message;
  EXPECT_EQ(tr.steps, StallWatch::kWindowSteps);
  EXPECT_NE(tr.message.find("advanced the time by"), std::string::npos) << tr.message;
  EXPECT_LT(tr.t.back(), 1e-5);
}

}  // namespace
}  // namespace rover
