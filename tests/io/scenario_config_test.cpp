// Scenario files (io/scenario_config.cpp; docs/model.md §7): the shipped
// scenarios load with the initial states of Table 2 and the obstacle runs'
// speeds, durations and ground clearance; bad files are refused with a
// ConfigError naming the file, the field and the value; recordings too large
// for memory and starts with a wheel deep in the ground are refused at load.
#include "io/scenario_config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "core/kinematic_tree.hpp"
#include "core/number_text.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using io::Json;
using testing::source_path;

// Height of each wheel's lowest rim point above z = 0 at q.
std::array<double, kNumLegs> wheel_bottoms(const RoverModel& model, const Coordinates& q) {
  const TreeKinematics kin = forward_kinematics(model.tree, q, Coordinates::Zero());
  std::array<double, kNumLegs> bottom{};
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const NodeKinematics& w = kin.nodes[node::wheel(leg)];
    const double s_z = w.rotation(2, 1);  // spin axis z component
    bottom[leg] = w.origin.z() - model.parameters.geometry.wheel_radius_m * std::sqrt(1.0 - s_z * s_z);
  }
  return bottom;
}

// The files a scenario names are listed by the fields that name them, each
// with where it was named, so that no output can replace one of them.
TEST(ScenarioConfig, ListsTheFilesItNames) {
  const std::string path = source_path("configs/scenarios/obstacle_v1.json");
  const io::ScenarioSources sources = io::read_scenario_sources(path);
  ASSERT_EQ(sources.files.files().size(), 2u);
  EXPECT_EQ(sources.files.files()[0].named_by, "'rover' in " + path);
  EXPECT_TRUE(std::filesystem::equivalent(sources.files.files()[0].path, source_path("configs/rover.json")));
  EXPECT_EQ(sources.files.files()[1].named_by, "'terrain' in " + path);
  EXPECT_TRUE(std::filesystem::equivalent(sources.files.files()[1].path, source_path("configs/terrains/obstacle.json")));
  EXPECT_NE(sources.files.same_file_as(source_path("configs/terrains/obstacle.json")), nullptr);
  EXPECT_EQ(sources.files.same_file_as(path), nullptr);  // the scenario itself is named by its caller
}

TEST(ScenarioConfig, DropScenariosHaveTheInitialStatesOfTable2) {
  struct Case {
    const char* file;
    double z, chi, psi;
  };
  for (const Case& c : {Case{"drop_horizontal", 0.281, 0.039, 0.0042}, Case{"drop_skewed", 0.299, 0.116, -0.0809}}) {
    const io::ScenarioSetup s = io::load_scenario(source_path("configs/scenarios/" + std::string(c.file) + ".json"));
    SCOPED_TRACE(c.file);
    EXPECT_EQ(s.scenario.name, c.file);
    Coordinates q = Coordinates::Zero();
    q[coord::z] = c.z;
    q[coord::pitch] = c.chi;
    q[coord::roll] = c.psi;
    EXPECT_EQ(s.scenario.initial_q, q);
    EXPECT_EQ(s.scenario.initial_u, Coordinates::Zero());
    EXPECT_EQ(s.scenario.duration_s, 1.0);
    EXPECT_EQ(s.scenario.output_rate_hz, 1000.0);
    EXPECT_EQ(s.scenario.integrator.method, IntegratorMethod::kDormandPrince45);
    EXPECT_EQ(s.scenario.integrator.relative_tolerance, 1e-6);
    EXPECT_EQ(s.scenario.integrator.absolute_tolerance, 1e-9);
    EXPECT_EQ(s.scenario.wheel_speed_ref_radps, (std::array<double, 4>{}));
    EXPECT_TRUE(s.model.terrain.is_flat());
    EXPECT_EQ(s.model.terrain.flat_height(), 0.0);
    // The inputs are the rover config's nominal values.
    EXPECT_EQ(s.inputs.sharpness_f, s.model.parameters.s_structure.sharpness_f);
    EXPECT_EQ(s.inputs.damping_c_q, s.model.parameters.s_structure.damping_c_q);
    EXPECT_EQ(s.inputs.preload_Nm, s.model.parameters.s_structure.preload_mean_Nm);
    // Released above the ground.
    for (double b : wheel_bottoms(s.model, s.scenario.initial_q)) EXPECT_GT(b, 0.0);
  }
}

TEST(ScenarioConfig, ObstacleScenariosDriveTheDistanceWithOneMillimetreClearance) {
  for (const auto& [file, v] : {std::pair{"obstacle_v034", 0.34}, std::pair{"obstacle_v1", 1.0},
                                std::pair{"obstacle_v2", 2.0}}) {
    SCOPED_TRACE(file);
    const io::ScenarioSetup s = io::load_scenario(source_path("configs/scenarios/" + std::string(file) + ".json"));
    const double R = s.model.parameters.geometry.wheel_radius_m;
    EXPECT_DOUBLE_EQ(s.scenario.duration_s, 2.869 / v);
    EXPECT_EQ(s.scenario.initial_u[coord::x], v);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      EXPECT_DOUBLE_EQ(s.scenario.initial_u[coord::spin(leg)], v / R);
      EXPECT_DOUBLE_EQ(s.scenario.wheel_speed_ref_radps[leg], v / R);
    }
    // Level chassis at the origin, joints at 0; only z set by the clearance.
    Coordinates q = Coordinates::Zero();
    q[coord::z] = s.scenario.initial_q[coord::z];
    EXPECT_EQ(s.scenario.initial_q, q);
    for (double b : wheel_bottoms(s.model, s.scenario.initial_q)) EXPECT_NEAR(b, 0.001, 1e-12);
    EXPECT_NEAR(q[coord::z], 0.2285 + 0.001, 1e-12);  // docs/model.md §3: bottoms 0.2285 m below G
    // The obstacle terrain: its top is 0.1 m, in front of the right wheels.
    ASSERT_FALSE(s.model.terrain.is_flat());
    EXPECT_NEAR(s.model.terrain.max_height(), 0.1, 1e-12);
    EXPECT_NEAR(s.model.terrain.height(1.8, -0.2215), 0.1, 1e-12);
    EXPECT_EQ(s.model.terrain.height(1.8, 0.2215), 0.0);
    EXPECT_EQ(s.terrain_path, source_path("configs/terrains/obstacle.json"));
  }
}

TEST(ScenarioConfig, EveryShippedScenarioLoads) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(source_path("configs/scenarios"))) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW({
      const io::ScenarioSetup s = io::load_scenario(entry.path().string());
      EXPECT_GT(s.scenario.duration_s, 0.0);
      EXPECT_EQ(s.scenario.name, entry.path().stem().string());
    });
    ++count;
  }
  EXPECT_GE(count, 5);
}

// ---------------------------------------------------------------- bad files

// A small valid scenario: the shipped horizontal drop with absolute paths.
Json base_scenario() {
  Json j = io::read_json_file(source_path("configs/scenarios/drop_horizontal.json"));
  j["rover"] = source_path("configs/rover.json");
  j["terrain"] = source_path("configs/terrains/flat.json");
  return j;
}

std::string write_scenario(const Json& j) {
  const std::string path = testing::temp_dir() + "/scenario.json";
  std::ofstream(path) << j.dump(2);
  return path;
}

// The base scenario with this "integrator" block: the error it is refused
// with, or "accepted".
std::string integrator_error(const Json& integrator) {
  Json j = base_scenario();
  j["integrator"] = integrator;
  try {
    io::load_scenario(write_scenario(j));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "accepted";
}

// Integrator settings that cannot work are refused when the file is read,
// naming the field and the numbers as written.
TEST(ScenarioConfig, InvalidIntegratorSettingsAreRefused) {
  const std::string steps = integrator_error({{"min_step", 1e-3}});  // above initial_step 1e-5
  EXPECT_NE(steps.find("min_step"), std::string::npos) << steps;
  EXPECT_NE(steps.find("0.001 <= 1e-05"), std::string::npos) << steps;
  const std::string rk4 = integrator_error({{"method", "rk4"}, {"fixed_step", 0.5}});  // 1 kHz output
  EXPECT_NE(rk4.find("does not divide the output period"), std::string::npos) << rk4;
  EXPECT_EQ(integrator_error({{"method", "rk4"}, {"fixed_step", 2e-5}}), "accepted");
}

TEST(ScenarioConfig, OverridesAreRead) {
  Json j = base_scenario();
  j["inputs"] = {{"f", 1e3}, {"c_q", 0.3}, {"M0", {1, 2, 3, 4, 5, 6, 7, 8}}};
  j["integrator"] = {{"method", "rk4"}, {"fixed_step", 2e-5}};
  j["initial_u"] = {{"b21", 0.5}, {"z3", -1.0}};
  j["steer_ref"] = {0.1, 0.2, 0.3, 0.4};
  j["wall_time_budget"] = 12.5;
  const io::ScenarioSetup s = io::load_scenario(write_scenario(j));
  EXPECT_EQ(s.inputs.sharpness_f, 1e3);
  EXPECT_EQ(s.inputs.damping_c_q, 0.3);
  EXPECT_EQ(s.inputs.preload_Nm, (std::array<double, 8>{1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(s.scenario.integrator.method, IntegratorMethod::kRungeKutta4);
  EXPECT_EQ(s.scenario.integrator.fixed_step_s, 2e-5);
  EXPECT_EQ(s.scenario.initial_u[coord::s_joint(1, 0)], 0.5);
  EXPECT_EQ(s.scenario.initial_u[coord::spin(2)], -1.0);
  EXPECT_EQ(s.scenario.initial_u.cwiseAbs().sum(), 1.5);
  EXPECT_EQ(s.scenario.steer_ref_rad, (std::array<double, 4>{0.1, 0.2, 0.3, 0.4}));
  EXPECT_EQ(s.scenario.wall_time_budget_s, 12.5);
}

TEST(ScenarioConfig, AnotherMethodBringsItsOwnTolerances) {
  // The base scenario runs dopri5 at rtol 1e-6, atol 1e-9; naming rosenbrock
  // alone gives rosenbrock's defaults, explicit fields still win.
  Json j = base_scenario();
  j["integrator"] = {{"method", "rosenbrock"}};
  const IntegratorSettings rosenbrock = default_integrator_settings(IntegratorMethod::kRosenbrockW);
  io::ScenarioSetup s = io::load_scenario(write_scenario(j));
  EXPECT_EQ(s.scenario.integrator.method, IntegratorMethod::kRosenbrockW);
  EXPECT_EQ(s.scenario.integrator.relative_tolerance, rosenbrock.relative_tolerance);
  EXPECT_EQ(s.scenario.integrator.absolute_tolerance, rosenbrock.absolute_tolerance);
  j["integrator"]["atol"] = 2e-4;
  s = io::load_scenario(write_scenario(j));
  EXPECT_EQ(s.scenario.integrator.relative_tolerance, rosenbrock.relative_tolerance);
  EXPECT_EQ(s.scenario.integrator.absolute_tolerance, 2e-4);
  EXPECT_EQ(s.scenario.integrator.slip_tolerance, rosenbrock.slip_tolerance);
}

TEST(ScenarioConfig, SlipToleranceIsReadAndCheckedByName) {
  Json j = base_scenario();
  j["integrator"] = {{"method", "rosenbrock"}, {"slip_tol", 0.01}};
  EXPECT_EQ(io::load_scenario(write_scenario(j)).scenario.integrator.slip_tolerance, 0.01);
  j["integrator"]["slip_tol"] = 2.0;
  try {
    io::load_scenario(write_scenario(j));
    ADD_FAILURE() << "slip_tol 2 accepted";
  } catch (const std::exception& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("slip_tol"), std::string::npos) << message;
    EXPECT_NE(message.find("got 2"), std::string::npos) << message;
  }
}

TEST(ScenarioConfig, BadFilesNameFileFieldAndValue) {
  const struct {
    const char* name;
    std::function<void(Json&)> edit;
    std::string field, problem, value;  // value: "" if the field is absent
  } cases[] = {
      {"unknown key", [](Json& j) { j["duratoin"] = 1.0; }, "duratoin", "unknown key", "1.0"},
      {"unknown integrator key", [](Json& j) { j["integrator"]["r_tol"] = 1e-6; }, "integrator.r_tol",
       "unknown key", "1e-06"},
      {"unknown coordinate", [](Json& j) { j["initial_q"]["zz"] = 0.3; }, "initial_q.zz",
       "unknown coordinate", "0.3"},
      {"unknown speed coordinate", [](Json& j) { j["initial_u"] = {{"b13", 1.0}}; }, "initial_u.b13",
       "unknown coordinate", "1.0"},
      {"duration and travel distance",
       [](Json& j) {
         j["forward_speed"] = 1.0;
         j["travel_distance"] = 2.869;
       },
       "duration", "exactly one", "1.0"},
      {"neither duration nor travel distance", [](Json& j) { j.erase("duration"); }, "duration",
       "exactly one", ""},
      {"travel distance without speed",
       [](Json& j) {
         j.erase("duration");
         j["travel_distance"] = 2.869;
       },
       "travel_distance", "forward_speed", "2.869"},
      {"missing rover file", [](Json& j) { j["rover"] = "/nonexistent/rover.json"; }, "rover",
       "file not found", "/nonexistent/rover.json"},
      {"missing terrain file", [](Json& j) { j["terrain"] = "no_such_terrain.json"; }, "terrain",
       "file not found", "no_such_terrain.json"},
      {"unknown integrator", [](Json& j) { j["integrator"]["method"] = "rk99"; }, "integrator.method",
       "unknown integrator", "rk99"},
      {"negative duration", [](Json& j) { j["duration"] = -1.0; }, "duration", "positive", "-1.0"},
      {"7 preloads", [](Json& j) { j["inputs"] = {{"M0", {1, 1, 1, 1, 1, 1, 1}}}; }, "inputs.M0",
       "expected 8 numbers, got 7", "[1,1,1,1,1,1,1]"},
      {"zero output rate", [](Json& j) { j["output_rate"] = 0; }, "output_rate", "positive", "0"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    Json j = base_scenario();
    c.edit(j);
    const std::string path = write_scenario(j);
    try {
      io::load_scenario(path);
      ADD_FAILURE() << "loaded:\n" << j.dump(2);
    } catch (const io::ConfigError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path), std::string::npos) << message;
      EXPECT_NE(message.find("'" + c.field + "'"), std::string::npos) << message;
      EXPECT_NE(message.find(c.problem), std::string::npos) << message;
      EXPECT_NE(message.find(c.value), std::string::npos) << message;
    }
  }
}

TEST(ScenarioConfig, ErrorsInTheRoverFileNameThatFile) {
  Json rover = io::read_json_file(source_path("configs/rover.json"));
  rover["drive"]["tau_max"] = -4.1;
  const std::string dir = testing::temp_dir();
  std::ofstream(dir + "/rover.json") << rover.dump(2);
  Json j = base_scenario();
  j["rover"] = "rover.json";  // relative to the scenario file
  const std::string path = dir + "/scenario.json";
  std::ofstream(path) << j.dump(2);
  try {
    io::load_scenario(path);
    ADD_FAILURE() << "loaded";
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/rover.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'drive.tau_max'"), std::string::npos) << e.what();
  }
}

// The ConfigError message of loading `j` (fails the test if it loads).
std::string load_error(const Json& j) {
  const std::string path = write_scenario(j);
  try {
    io::load_scenario(path);
  } catch (const io::ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "loaded:\n" << j.dump(2);
  return "";
}

// The chassis's angular rates are bounded by the rover's own size: at the
// bound, no wheel rim moves faster than the 10 m/s that bounds the linear
// speeds (the rates of a turning rover, from its kinematics); 110 rad/s of
// yaw, pitch or roll is refused, naming the field, the value and the range,
// while a wheel may still spin at 110 rad/s (its rim at 9.4 m/s).
TEST(ScenarioConfig, ChassisRatesAreBoundedByTheRoversExtent) {
  const io::ScenarioSetup nominal = io::load_scenario(write_scenario(base_scenario()));
  const io::SpeedScale scale = io::speed_scale(nominal.model);
  const double bound = 10.0 / scale.rover_extent_m;
  for (const int index : {coord::yaw, coord::pitch, coord::roll}) {
    Coordinates u = Coordinates::Zero();
    u[index] = bound;
    const TreeKinematics kin = forward_kinematics(nominal.model.tree, Coordinates::Zero(), u);
    double fastest_rim = 0.0;
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const NodeKinematics& w = kin.nodes[node::wheel(leg)];
      fastest_rim = std::max(fastest_rim, w.velocity.norm() + w.omega.norm() * scale.wheel_radius_m);
    }
    EXPECT_LE(fastest_rim, 10.0 * (1 + 1e-12)) << kCoordinateNames[index];
    EXPECT_GE(fastest_rim, 5.0) << kCoordinateNames[index];  // the bound is the rover's, not far looser
  }
  for (const char* name : {"theta", "chi", "psi"}) {
    SCOPED_TRACE(name);
    Json j = base_scenario();
    j["initial_u"] = {{name, 110.0}};
    const std::string path = write_scenario(j);
    try {
      io::load_scenario(path);
      ADD_FAILURE() << "loaded " << name << " = 110 rad/s";
    } catch (const io::ConfigError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("'initial_u'"), std::string::npos) << message;
      EXPECT_NE(message.find(std::string(name) + " = 110 rad/s is beyond +-" + number_text(bound) + " rad/s"),
                std::string::npos) << message;
      EXPECT_NE(message.find("the rover's farthest point"), std::string::npos) << message;
    }
    j["initial_u"] = {{name, 0.99 * bound}};
    EXPECT_NO_THROW(io::load_scenario(write_scenario(j)));
  }
  Json j = base_scenario();
  j["initial_u"] = {{"z1", 110.0}};
  EXPECT_NO_THROW(io::load_scenario(write_scenario(j)));
}

TEST(ScenarioConfig, RecordingSizeEstimateIsTheClosedForm) {
  // 1e12 s at 1 kHz: 1e15 + 1 samples of 56 doubles (448 bytes) = 448 PB.
  EXPECT_EQ(io::kTrajectoryBytesPerSample, 448.0);
  EXPECT_EQ(io::recorded_sample_count(3600.0, 1e3), 3600001.0);
  EXPECT_EQ(io::recorded_sample_count(0.2, 1e3), 201.0);  // as output_sample_count
  const std::string problem = io::recording_size_problem(1e15, io::kTrajectoryBytesPerSample);
  EXPECT_NE(problem.find("would record 1.0e+15 samples (448 PB"), std::string::npos) << problem;
  // The bound: 8 GiB exactly is allowed, one sample more is not.
  const double samples_at_bound = io::kMaxRecordingBytes / io::kTrajectoryBytesPerSample;
  EXPECT_EQ(io::recording_size_problem(std::floor(samples_at_bound), io::kTrajectoryBytesPerSample), "");
  EXPECT_NE(io::recording_size_problem(std::floor(samples_at_bound) + 1.0, io::kTrajectoryBytesPerSample), "");
}

TEST(ScenarioConfig, AbsurdRecordingsAreRefusedWithTheirSize) {
  const struct {
    std::function<void(Json&)> edit;
    std::string field, samples;
  } cases[] = {
      {[](Json& j) { j["duration"] = 1e12; }, "duration", "1.0e+15 samples"},
      {[](Json& j) { j["output_rate"] = 1e9; }, "duration", "1.0e+09 samples"},
      {[](Json& j) {
         j["duration"] = 3600.0 * 24 * 365;
         j["output_rate"] = 100;
       },
       "duration", "3.2e+09 samples"},
      {[](Json& j) {
         j.erase("duration");
         j["forward_speed"] = 1e-9;
         j["travel_distance"] = 1.0;
       },
       "travel_distance", "1.0e+12 samples"},
  };
  for (const auto& c : cases) {
    Json j = base_scenario();
    c.edit(j);
    const std::string message = load_error(j);
    EXPECT_NE(message.find("'" + c.field + "'"), std::string::npos) << message;
    EXPECT_NE(message.find("would record " + c.samples), std::string::npos) << message;
    EXPECT_NE(message.find("reduce duration or output_rate"), std::string::npos) << message;
  }
  // An hour at 1 kHz (1.6 GB) is allowed.
  Json hour = base_scenario();
  hour["duration"] = 3600.0;
  EXPECT_NO_THROW(io::load_scenario(write_scenario(hour)));
}

TEST(ScenarioConfig, PenetrationToleranceCarriesTheWeightOnOneWheel) {
  const io::ScenarioSetup s = io::load_scenario(write_scenario(base_scenario()));
  const RoverParameters& p = s.model.parameters;
  const double tolerance = io::initial_penetration_tolerance_m(s.model);
  // k_g p^sigma = m g at the tolerance.
  EXPECT_NEAR(p.contact.stiffness_k_g * std::pow(tolerance, p.contact.exponent_sigma),
              s.model.tree.total_mass_kg * p.gravity_mps2, 1e-9);
  EXPECT_GT(tolerance, 1e-3);
  EXPECT_LT(tolerance, 1e-2);
  // initial_ground_clearance c < 0 puts the lowest wheel exactly -c into flat ground.
  for (const double clearance : {-0.0005, -0.002, -0.03, -0.15}) {
    SCOPED_TRACE(clearance);
    Json j = base_scenario();
    j.erase("initial_q");
    j["initial_ground_clearance"] = clearance;
    const std::string path = write_scenario(j);
    if (-clearance <= tolerance) {
      const io::ScenarioSetup ok = io::load_scenario(path);
      EXPECT_NEAR(io::deepest_wheel_penetration(ok.model, ok.scenario.initial_q).depth_m, -clearance, 1e-12);
      continue;
    }
    const std::string message = load_error(j);
    EXPECT_NE(message.find("'initial_ground_clearance'"), std::string::npos) << message;
    EXPECT_NE(message.find("below the ground"), std::string::npos) << message;
  }
}

TEST(ScenarioConfig, StartsWithAWheelInTheGroundAreRefusedByField) {
  for (const double z : {0.0, 0.1, 0.15, -2.0}) {
    SCOPED_TRACE(z);
    Json j = base_scenario();
    j["initial_q"]["z"] = z;
    const std::string message = load_error(j);
    EXPECT_NE(message.find("'initial_q'"), std::string::npos) << message;
    EXPECT_NE(message.find("starts"), std::string::npos) << message;
    EXPECT_NE(message.find("below the ground"), std::string::npos) << message;
  }
  // A steep pitch puts one axle's wheels into the ground.
  Json pitched = base_scenario();
  pitched["initial_q"]["chi"] = 0.6;
  EXPECT_NE(load_error(pitched).find("below the ground"), std::string::npos);
  // Dropping from 3 m is allowed (it lands at 7.3 m/s; the run is judged
  // after it); from 10 m it would land at 13.8 m/s, beyond the speed bound.
  Json high = base_scenario();
  high["initial_q"]["z"] = 3.0;
  EXPECT_NO_THROW(io::load_scenario(write_scenario(high)));
  high["initial_q"]["z"] = 10.0;
  const std::string landing = load_error(high);
  EXPECT_NE(landing.find("lands at 13.8"), std::string::npos) << landing;
  EXPECT_NE(landing.find("beyond +-10 m/s"), std::string::npos) << landing;
  // Every shipped scenario starts above or on the ground.
  for (const auto& entry : std::filesystem::directory_iterator(source_path("configs/scenarios"))) {
    const io::ScenarioSetup s = io::load_scenario(entry.path().string());
    EXPECT_LE(io::deepest_wheel_penetration(s.model, s.scenario.initial_q).depth_m,
              io::initial_penetration_tolerance_m(s.model))
        << entry.path();
  }
}

// A name inside a config means what the system makes of it: ".." after a
// linked folder leaves the link's target. Plain names keep their tidy form.
TEST(ResolveRelative, FollowsLinkedFoldersAsTheSystemDoes) {
  namespace fs = std::filesystem;
  const fs::path base = rover::testing::temp_dir();
  fs::create_directories(base / "configs" / "scenarios");
  fs::create_directories(base / "elsewhere" / "sub");
  fs::create_directory_symlink(base / "elsewhere" / "sub", base / "configs" / "lnk");
  for (const fs::path& file : {base / "configs" / "rover.json", base / "elsewhere" / "rover.json"})
    std::ofstream(file) << "{}\n";
  const std::string config = (base / "configs" / "s.json").string();
  const std::string through_link = io::resolve_relative(config, "lnk/../rover.json");
  EXPECT_TRUE(fs::equivalent(through_link, base / "elsewhere" / "rover.json")) << through_link;
  EXPECT_EQ(io::resolve_relative((base / "configs" / "scenarios" / "s.json").string(), "../rover.json"),
            (base / "configs" / "rover.json").string());
  EXPECT_EQ(io::resolve_relative(config, "/abs/x.json"), "/abs/x.json");
}

TEST(ScenarioConfig, KeysTheMethodDoesNotUseAreRefusedByName) {
  const std::string slip_on_dopri5 = integrator_error({{"method", "dopri5"}, {"slip_tol", 0.01}});
  EXPECT_NE(slip_on_dopri5.find("'integrator.slip_tol'"), std::string::npos) << slip_on_dopri5;
  const std::string rtol_on_rk4 = integrator_error({{"method", "rk4"}, {"fixed_step", 2e-5}, {"rtol", 1e-8}});
  EXPECT_NE(rtol_on_rk4.find("'integrator.rtol'"), std::string::npos) << rtol_on_rk4;
  EXPECT_NE(rtol_on_rk4.find("fixed_step"), std::string::npos) << rtol_on_rk4;
  const std::string step_on_rodas4 = integrator_error({{"method", "rodas4"}, {"fixed_step", 1e-5}});
  EXPECT_NE(step_on_rodas4.find("'integrator.fixed_step'"), std::string::npos) << step_on_rodas4;
  // The keys each method uses are accepted.
  EXPECT_EQ(integrator_error({{"method", "rodas4"}, {"slip_tol", 0.02}, {"max_step", 1e-3}}), "accepted");
  EXPECT_EQ(integrator_error({{"method", "dopri5"}, {"rtol", 1e-8}, {"atol", 1e-11}, {"initial_step", 1e-6}}), "accepted");
}


// The chassis's pitch and roll and the bogie's angle within a quarter turn,
// its heading and the wheels' rolling angles within a full turn: an angle
// beyond is one in degrees, refused naming the field, the value and the bound;
// one within loads.
TEST(ScenarioConfig, PoseAnglesInDegreesAreRefused) {
  const struct {
    const char* name;
    double bound;
  } angles[] = {{"chi", std::numbers::pi / 2}, {"psi", std::numbers::pi / 2}, {"phi", std::numbers::pi / 2},
                {"theta", 2 * std::numbers::pi}, {"z1", 2 * std::numbers::pi}, {"z4", 2 * std::numbers::pi}};
  for (const auto& angle : angles) {
    SCOPED_TRACE(angle.name);
    Json j = base_scenario();
    j["initial_q"] = {{"z", 0.6}, {angle.name, 30.0}};
    const std::string message = load_error(j);
    EXPECT_NE(message.find("'initial_q'"), std::string::npos) << message;
    EXPECT_NE(message.find(std::string(angle.name) + " = 30 rad is beyond +-" + number_text(angle.bound) + " rad"),
              std::string::npos) << message;
    EXPECT_NE(message.find("an angle in degrees?"), std::string::npos) << message;
    // Within the bound the pose is the loader's to judge (a wheel in the ground
    // is its own refusal): a small angle loads.
    j["initial_q"] = {{"z", 0.6}, {angle.name, 0.1}};
    EXPECT_NO_THROW(io::load_scenario(write_scenario(j)));
  }
  const io::ScenarioSetup nominal = io::load_scenario(write_scenario(base_scenario()));
  Coordinates q = Coordinates::Zero();
  q[coord::yaw] = 1e17;
  EXPECT_NE(io::pose_angle_problem(nominal.model, q).find("theta = 1e+17 rad"), std::string::npos);
  q[coord::yaw] = -6.0;
  EXPECT_EQ(io::pose_angle_problem(nominal.model, q), "");
}

}  // namespace
}  // namespace rover

// A method named alone replaces all the settings of another method, step
// limits included: a Rosenbrock run at dopri5's min_step would fail.
TEST(IntegratorSettings, AnotherMethodBringsAllItsOwnSettings) {
  rover::IntegratorSettings base = rover::default_integrator_settings(rover::IntegratorMethod::kDormandPrince45);
  base.min_step_s = 0.002;
  base.initial_step_s = 0.002;
  base.max_step_s = 0.01;
  const rover::io::Json block = {{"method", "rosenbrock"}};
  const rover::IntegratorSettings parsed =
      rover::io::parse_integrator_settings(rover::io::JsonReader(block, "study.json", "integrator"), base);
  const rover::IntegratorSettings own = rover::default_integrator_settings(rover::IntegratorMethod::kRosenbrockW);
  EXPECT_EQ(parsed.method, rover::IntegratorMethod::kRosenbrockW);
  EXPECT_EQ(parsed.min_step_s, own.min_step_s);
  EXPECT_EQ(parsed.initial_step_s, own.initial_step_s);
  EXPECT_EQ(parsed.max_step_s, own.max_step_s);
  EXPECT_EQ(parsed.relative_tolerance, own.relative_tolerance);
}
