// Scenarios with a "drive" block (io/scenario_config.hpp): the
// schedule is parsed in either command form, the initial state rolls without
// slip, a simulated Ackermann turn follows its radius, an in-place rotation
// turns about G, a bad block is rejected naming the file and the field, and
// the README's example block parses as written.
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "core/drive_kinematics.hpp"
#include "core/kinematic_tree.hpp"
#include "core/simulate.hpp"
#include "io/rover_config.hpp"
#include "io/scenario_config.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using io::ConfigError;
using io::load_scenario;
using io::ScenarioSetup;

std::string scenario_file(const std::string& name) {
  return testing::source_path("configs/scenarios/" + name + ".json");
}

// A scenario file on flat ground with the given "drive" block (and extra
// top-level fields), lasting `duration_s` (every segment must start before
// it), in a fresh directory.
std::string write_drive_scenario(const std::string& drive, const std::string& extra = "",
                                 double duration_s = 1.0) {
  const std::string path = testing::temp_dir() + "/drive.json";
  std::ofstream(path) << R"({"rover": ")" << testing::source_path("configs/rover.json") << R"(", "duration": )"
                      << duration_s << R"(, "initial_ground_clearance": 0.001, )" << extra << R"("drive": )"
                      << drive << "}";
  return path;
}

// Velocity of the material point of each wheel at its lowest rim point.
std::array<Vec3, kNumLegs> rim_bottom_velocities(const RoverModel& model, const Coordinates& q,
                                                 const Coordinates& u) {
  const TreeKinematics kin = forward_kinematics(model.tree, q, u);
  const double R = model.parameters.geometry.wheel_radius_m;
  std::array<Vec3, kNumLegs> v;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const NodeKinematics& w = kin.nodes[node::wheel(leg)];
    v[leg] = w.velocity + w.omega.cross(Vec3(0.0, 0.0, -R));
  }
  return v;
}

// Algebraic (Kasa) least-squares circle through the points: centre and radius.
std::pair<Vec2, double> fit_circle(const std::vector<Vec2>& points) {
  Eigen::MatrixXd A(static_cast<Eigen::Index>(points.size()), 3);
  Eigen::VectorXd b(A.rows());
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    const Vec2& p = points[static_cast<std::size_t>(i)];
    A.row(i) << 2.0 * p.x(), 2.0 * p.y(), 1.0;
    b[i] = p.squaredNorm();
  }
  const Eigen::Vector3d c = A.colPivHouseholderQr().solve(b);
  const Vec2 centre(c[0], c[1]);
  return {centre, std::sqrt(c[2] + centre.squaredNorm())};
}

constexpr double kSettledAfter_s = 0.5;  // the drop from 1 mm is over by then

TEST(DriveScenario, NaturalAndBodyFormsGiveTheSameSchedule) {
  const ScenarioSetup natural = load_scenario(write_drive_scenario(
      R"({"ramp_time": 0.2, "segments": [{"mode": "ackermann", "speed": 0.3, "radius": -1.5},
          {"start": 1.0, "mode": "parallel", "speed": 0.2, "crab_angle": 0.5}]})", "", 2.0));
  // The same motions as body velocities: G on a -1.5 m radius at 0.3 m/s
  // (G is midway between the axles), then 0.2 m/s at 0.5 rad to the left.
  std::ostringstream crab;
  crab << std::setprecision(17) << R"("forward": )" << 0.2 * std::cos(0.5) << R"(, "lateral": )"
       << 0.2 * std::sin(0.5);
  const ScenarioSetup body = load_scenario(write_drive_scenario(
      R"({"ramp_time": 0.2, "segments": [{"mode": "ackermann", "forward": 0.3, "yaw_rate": -0.2},
          {"start": 1.0, "mode": "parallel", )" + crab.str() + "}]}", "", 2.0));
  const DriveSchedule& a = natural.scenario.drive;
  const DriveSchedule& b = body.scenario.drive;
  ASSERT_EQ(a.segments.size(), 2u);
  ASSERT_EQ(b.segments.size(), 2u);
  EXPECT_DOUBLE_EQ(a.options.ramp_time_s, 0.2);
  const CompiledDriveSchedule compiled_a(make_drive_kinematics(natural.model.parameters), a.segments,
                                         a.options);
  const CompiledDriveSchedule compiled_b(make_drive_kinematics(body.model.parameters), b.segments,
                                         b.options);
  for (double t : {0.0, 0.5, 1.05, 1.1, 2.0}) {
    const WheelCommands wa = compiled_a.at(t);
    const WheelCommands wb = compiled_b.at(t);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      EXPECT_NEAR(wa.steer_rad[leg], wb.steer_rad[leg], 1e-12) << "t " << t << " leg " << leg;
      EXPECT_NEAR(wa.wheel_speed_radps[leg], wb.wheel_speed_radps[leg], 1e-12) << "t " << t;
    }
  }
}

// "commanded": the rover starts with the commanded motion, every wheel
// rolling without slip; "rest": no motion, but already steered.
TEST(DriveScenario, InitialStateRollsWithoutSlip) {
  for (const char* name : {"turn_ackermann", "in_place_rotation"}) {
    const ScenarioSetup setup = load_scenario(scenario_file(name));
    const Scenario& s = setup.scenario;
    ASSERT_FALSE(s.drive.segments.empty()) << name;
    const auto v = rim_bottom_velocities(setup.model, s.initial_q, s.initial_u);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      EXPECT_LT(v[leg].norm(), 1e-12) << name << " wheel " << kWheelNames[leg];
      EXPECT_GT(std::abs(s.initial_u[coord::spin(leg)]), 0.1) << name;  // it does roll
    }
    EXPECT_GT(std::abs(s.initial_u[coord::yaw]), 0.1) << name;
  }
  const ScenarioSetup rest = load_scenario(write_drive_scenario(
      R"({"initial_motion": "rest", "segments": [{"mode": "rotation", "yaw_rate": 0.5}]})"));
  EXPECT_TRUE(rest.scenario.initial_u.isZero(0.0));
  for (int leg = 0; leg < kNumLegs; ++leg)  // tangent to the circle about G: |d| > 0
    EXPECT_GT(std::abs(rest.scenario.initial_q[coord::steer(leg)]), 0.3);
}

TEST(DriveScenario, ExplicitInitialSpeedsOverrideTheCommandedOnes) {
  const ScenarioSetup setup = load_scenario(write_drive_scenario(
      R"({"segments": [{"mode": "parallel", "speed": 0.4}]})", R"("initial_u": {"x": 0.1}, )"));
  EXPECT_DOUBLE_EQ(setup.scenario.initial_u[coord::x], 0.1);
  EXPECT_NEAR(setup.scenario.initial_u[coord::spin(0)] * setup.model.parameters.geometry.wheel_radius_m,
              0.4, 1e-12);
}

// At low speed (0.3 m/s, lateral acceleration 0.09 m/s^2 against mu_k 0.2)
// the wheels barely slip, so G follows the commanded 1 m circle.
TEST(DriveScenario, AckermannTurnFollowsItsRadius) {
  ScenarioSetup setup = load_scenario(scenario_file("turn_ackermann"));
  Scenario& s = setup.scenario;
  s.duration_s = 2.0;  // 0.45 rad of arc after settling
  const Trajectory tr = simulate(setup.model, s, setup.inputs);
  ASSERT_TRUE(tr.ok()) << tr.message;

  const DriveCommandSegment& command = s.drive.segments.front();
  const double radius_m = command.command.forward_mps / command.command.yaw_rate_radps;
  ASSERT_NEAR(radius_m, 1.0, 1e-12);  // the file asks for R = 1 m
  std::vector<Vec2> path;
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    if (tr.t[i] >= kSettledAfter_s)
      path.emplace_back(tr.q(static_cast<Eigen::Index>(i), coord::x),
                        tr.q(static_cast<Eigen::Index>(i), coord::y));
  }
  ASSERT_GT(path.size(), 100u);
  const auto [centre, fitted_radius_m] = fit_circle(path);
  EXPECT_NEAR(fitted_radius_m / radius_m, 1.0, 0.03);
  // The centre is the commanded ICR, to the left of the start.
  EXPECT_LT((centre - Vec2(0.0, radius_m)).norm(), 0.03 * radius_m);
  // Travelled at the commanded speed.
  const double chord_m = (path.back() - path.front()).norm();
  const double chord_expected_m =
      2.0 * radius_m * std::sin(0.5 * command.command.forward_mps * (s.duration_s - kSettledAfter_s) / radius_m);
  EXPECT_NEAR(chord_m / chord_expected_m, 1.0, 0.03);
}

TEST(DriveScenario, InPlaceRotationTurnsAboutG) {
  ScenarioSetup setup = load_scenario(scenario_file("in_place_rotation"));
  Scenario& s = setup.scenario;
  s.duration_s = 1.5;  // 0.5 rad after settling
  const Trajectory tr = simulate(setup.model, s, setup.inputs);
  ASSERT_TRUE(tr.ok()) << tr.message;

  const double yaw_rate = s.drive.segments.front().command.yaw_rate_radps;
  ASSERT_GT(yaw_rate, 0.0);
  const Eigen::Index last = tr.q.rows() - 1;
  const Vec2 start(tr.q(0, coord::x), tr.q(0, coord::y));
  double drift_m = 0.0;
  Eigen::Index settled = 0;
  for (Eigen::Index i = 0; i <= last; ++i) {
    drift_m = std::max(drift_m, (Vec2(tr.q(i, coord::x), tr.q(i, coord::y)) - start).norm());
    if (tr.t[static_cast<std::size_t>(i)] < kSettledAfter_s) settled = i + 1;
  }
  EXPECT_LT(drift_m, 0.003);
  const double turned = tr.q(last, coord::yaw) - tr.q(settled, coord::yaw);
  const double expected = yaw_rate * (tr.t.back() - tr.t[static_cast<std::size_t>(settled)]);
  EXPECT_NEAR(turned / expected, 1.0, 0.03);
}

// A bad "drive" block: a ConfigError naming the file, the field and why.
void expect_config_error(const std::string& drive, const std::string& field,
                         const std::string& why, const std::string& extra = "") {
  const std::string path = write_drive_scenario(drive, extra);
  try {
    load_scenario(path);
    ADD_FAILURE() << "no error for " << drive << " " << extra;
  } catch (const ConfigError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("'" + field + "'"), std::string::npos) << message;
    EXPECT_NE(message.find(why), std::string::npos) << message;
  }
}

TEST(DriveScenario, BadDriveBlockNamesFileAndField) {
  expect_config_error(R"({"segments": [{"mode": "tank", "speed": 1}]})",
                      "drive.segments[0].mode", "unknown driving mode");
  expect_config_error(R"({"segments": []})", "drive.segments", "non-empty array");
  expect_config_error(R"({"segments": [{"mode": "parallel", "forward": 0.2, "yaw_rate": 0.3}]})",
                      "drive.segments[0]", "cannot turn");
  expect_config_error(R"({"segments": [{"mode": "ackermann", "speed": 0.3, "forward": 0.3}]})",
                      "drive.segments[0].forward", "not both");
  expect_config_error(R"({"segments": [{"mode": "ackermann", "radius": 1.0}]})",
                      "drive.segments[0].radius", "needs 'speed'");
  expect_config_error(R"({"segments": [{"mode": "rotation", "speed": 0.3}]})",
                      "drive.segments[0].speed", "yaw_rate");
  expect_config_error(R"({"segments": [{"start": 0.5, "mode": "lateral", "speed": 0.1}]})",
                      "drive.segments[0].start", "must start at 0 s");
  expect_config_error(R"({"segments": [{"mode": "lateral", "speed": 0.1},
                                       {"mode": "lateral", "speed": 0.2}]})",
                      "drive.segments[1].start", "missing required field");
  expect_config_error(R"({"ramp_time": 0.5, "segments": [{"mode": "lateral", "speed": 0.1},
                          {"start": 1.0, "mode": "lateral", "speed": 0.2},
                          {"start": 1.2, "mode": "lateral", "speed": 0.0}]})",
                      "drive.segments", "shorter than the ramp time");
  expect_config_error(R"({"allow_flip": false, "segments": [{"mode": "rotation", "yaw_rate": -0.5}]})",
                      "drive.segments[0]", "allow_flip = false");
  expect_config_error(R"({"segments": [{"mode": "car", "speed": 0.3, "radius": 1, "icr": [0, 1]}]})",
                      "drive.segments[0].icr", "unknown key");
  expect_config_error(R"({"segments": [{"mode": "car", "speed": 0.3}]})", "forward_speed",
                      "conflicts with 'drive'", R"("forward_speed": 0.3, )");
}

// The ```json block after "**Driving commands.**" in README.md, as written.
std::string readme_drive_block() {
  std::ifstream in(testing::source_path("README.md"));
  std::stringstream text;
  text << in.rdbuf();
  const std::string readme = text.str();
  const std::size_t section = readme.find("**Driving commands.**");
  const std::size_t fence = readme.find("```json\n", section);
  const std::size_t begin = fence + 8;
  const std::size_t end = readme.find("```", begin);
  if (section == std::string::npos || fence == std::string::npos || end == std::string::npos)
    return "";
  return readme.substr(begin, end - begin);
}

TEST(DriveScenario, ReadmeExampleParsesAsWritten) {
  const std::string block = readme_drive_block();
  ASSERT_NE(block.find("\"drive\""), std::string::npos) << "no drive example in README.md";
  // As it appears in a scenario: a member of the top-level object.
  const io::Json scenario = io::parse_json_text("{" + block + "}", "README.md");
  const io::JsonReader top(scenario, "README.md");
  const DriveKinematics kinematics =
      make_drive_kinematics(io::load_rover_parameters(testing::source_path("configs/rover.json")));
  const io::DriveConfig drive = io::parse_drive(top.child("drive"), kinematics);
  top.finish();
  EXPECT_TRUE(drive.start_at_rest);
  EXPECT_EQ(drive.schedule.options.ramp_time_s, 0.3);
  ASSERT_EQ(drive.schedule.segments.size(), 5u);
  EXPECT_EQ(drive.schedule.segments[1].mode, DriveMode::kSymmetricAckermann);
  // ackermann at 0.3 m/s on a 1 m radius turns at 0.3 rad/s.
  EXPECT_NEAR(drive.schedule.segments[1].command.yaw_rate_radps, 0.3, 1e-12);
  EXPECT_EQ(drive.schedule.segments[4].mode, DriveMode::kInPlaceRotation);
  EXPECT_EQ(drive.schedule.segments[4].start_time_s, 4.0);
  // And in a whole scenario file.
  const std::string path = write_drive_scenario(block.substr(block.find('{')), "", 5.0);
  EXPECT_NO_THROW(load_scenario(path));
}

}  // namespace
}  // namespace rover
