// The rover config loader (io/rover_config.cpp): the shipped configs/rover.json
// is exactly docs/model.md's defaults (core/rover_parameters.cpp), and every kind of
// bad input is refused with a ConfigError naming the file, the field (dotted
// path) and the value. Bad configs are the shipped one with one edit, written
// to a temporary file.
#include "io/rover_config.hpp"

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace rover {
namespace {

using io::Json;
using testing::source_path;

void expect_same_body(const RigidBodyParameters& a, const RigidBodyParameters& b,
                      const std::string& name) {
  EXPECT_EQ(a.mass_kg, b.mass_kg) << name;
  EXPECT_EQ(a.com_m, b.com_m) << name;
  EXPECT_EQ(a.inertia_kgm2, b.inertia_kgm2) << name;
}

TEST(RoverConfig, ShippedConfigIsTheModelDefaults) {
  const RoverParameters a = io::load_rover_parameters(source_path("configs/rover.json"));
  const RoverParameters b = default_rover_parameters();
  EXPECT_EQ(a.gravity_mps2, b.gravity_mps2);

  EXPECT_EQ(a.geometry.bogie_pivot_m, b.geometry.bogie_pivot_m);
  EXPECT_EQ(a.geometry.hip_m, b.geometry.hip_m);
  EXPECT_EQ(a.geometry.knee_m, b.geometry.knee_m);
  EXPECT_EQ(a.geometry.wheel_centre_m, b.geometry.wheel_centre_m);
  EXPECT_EQ(a.geometry.wheel_radius_m, b.geometry.wheel_radius_m);

  expect_same_body(a.chassis, b.chassis, "chassis");
  expect_same_body(a.bogie, b.bogie, "bogie");
  expect_same_body(a.module1, b.module1, "module1");
  expect_same_body(a.module2, b.module2, "module2");
  expect_same_body(a.wheel, b.wheel, "wheel");

  EXPECT_EQ(a.s_structure.sharpness_f, b.s_structure.sharpness_f);
  EXPECT_EQ(a.s_structure.stiffness_Nm_per_rad, b.s_structure.stiffness_Nm_per_rad);
  EXPECT_EQ(a.s_structure.damping_c_q, b.s_structure.damping_c_q);
  EXPECT_EQ(a.s_structure.preload_mean_Nm, b.s_structure.preload_mean_Nm);
  EXPECT_EQ(a.s_structure.preload_sd_Nm, b.s_structure.preload_sd_Nm);

  EXPECT_EQ(a.steering.stiffness_Nm_per_rad, b.steering.stiffness_Nm_per_rad);
  EXPECT_EQ(a.steering.damping_Nms_per_rad, b.steering.damping_Nms_per_rad);
  EXPECT_EQ(a.steering.limit_rad, b.steering.limit_rad);
  EXPECT_EQ(a.steering.end_stop_stiffness_Nm_per_rad, b.steering.end_stop_stiffness_Nm_per_rad);

  EXPECT_EQ(a.drive.gain_Nms_per_rad, b.drive.gain_Nms_per_rad);
  EXPECT_EQ(a.drive.max_torque_Nm, b.drive.max_torque_Nm);

  EXPECT_EQ(a.contact.stiffness_k_g, b.contact.stiffness_k_g);
  EXPECT_EQ(a.contact.damping_c_g, b.contact.damping_c_g);
  EXPECT_EQ(a.contact.exponent_sigma, b.contact.exponent_sigma);

  EXPECT_EQ(a.friction.mu_static, b.friction.mu_static);
  EXPECT_EQ(a.friction.v_static_mps, b.friction.v_static_mps);
  EXPECT_EQ(a.friction.mu_kinetic, b.friction.mu_kinetic);
  EXPECT_EQ(a.friction.v_kinetic_mps, b.friction.v_kinetic_mps);
  EXPECT_EQ(a.friction.gammas, b.friction.gammas);
  EXPECT_EQ(a.friction.gammas_fitted_to, b.friction.gammas_fitted_to);
}

// The shipped config, parsed, for editing.
Json shipped_config() { return io::read_json_file(source_path("configs/rover.json")); }

// Writes `config` to a fresh file and returns the message of the ConfigError
// that loading it throws (fails the test if it loads).
std::string load_error(const Json& config, std::string* path_out = nullptr) {
  const std::string path = testing::temp_dir() + "/rover.json";
  std::ofstream(path) << config.dump(2);
  if (path_out) *path_out = path;
  try {
    io::load_rover_parameters(path);
  } catch (const io::ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "loading the edited config did not throw:\n" << config.dump(2);
  return "";
}

struct BadCase {
  std::string name;
  std::function<void(Json&)> edit;
  std::string field;    // dotted path the message must name
  std::string problem;  // part of the explanation
  bool names_value;     // the field exists, so its value must be quoted
};

TEST(RoverConfig, BadConfigsNameFileFieldAndValue) {
  const std::vector<BadCase> cases = {
      {"missing mass", [](Json& j) { j["bodies"]["wheel"].erase("mass"); }, "bodies.wheel.mass",
       "missing", false},
      {"missing section", [](Json& j) { j.erase("contact"); }, "contact", "missing", false},
      {"negative mass", [](Json& j) { j["bodies"]["module2"]["mass"] = -0.393; },
       "bodies.module2.mass", "positive", true},
      {"zero mass", [](Json& j) { j["bodies"]["chassis"]["mass"] = 0.0; }, "bodies.chassis.mass",
       "positive", true},
      {"zero hip length", [](Json& j) { j["geometry"]["hip"] = Json::array({0.0, 0.0, 0.0}); },
       "geometry.hip", "length", true},
      {"zero knee length", [](Json& j) { j["geometry"]["knee"] = Json::array({0.0, 0.0, 0.0}); },
       "geometry.knee", "length", true},
      {"negative wheel radius", [](Json& j) { j["geometry"]["wheel_radius"] = -0.085; },
       "geometry.wheel_radius", "positive", true},
      {"zero wheel radius", [](Json& j) { j["geometry"]["wheel_radius"] = 0.0; },
       "geometry.wheel_radius", "positive", true},
      {"non-symmetric inertia",
       [](Json& j) { j["bodies"]["chassis"]["inertia"][0][2] = 1.5e-4; },  // [2][0] stays -1.5e-4
       "bodies.chassis.inertia", "symmetric", true},
      {"negative principal inertia",
       [](Json& j) { j["bodies"]["bogie"]["inertia"][1][1] = -6.84e-4; }, "bodies.bogie.inertia",
       "positive definite", true},
      {"indefinite inertia with a positive diagonal",  // eigenvalues 3e-5, -1e-5, 1e-5
       [](Json& j) {
         j["bodies"]["module1"]["inertia"] =
             Json::array({Json::array({1e-5, 2e-5, 0.0}), Json::array({2e-5, 1e-5, 0.0}),
                          Json::array({0.0, 0.0, 1e-5})});
       },
       "bodies.module1.inertia", "positive definite", true},
      {"unknown top-level key", [](Json& j) { j["gravty"] = 9.81; }, "gravty", "unknown key",
       true},
      {"unknown nested key", [](Json& j) { j["contact"]["k_G"] = 1e6; }, "contact.k_G",
       "unknown key", true},
      {"unknown key in a body", [](Json& j) { j["bodies"]["wheel"]["radius"] = 0.085; },
       "bodies.wheel.radius", "unknown key", true},
      {"7 preload means",
       [](Json& j) { j["s_structure"]["preload_mean"].erase(7); }, "s_structure.preload_mean",
       "expected 8 numbers, got 7", true},
      {"9 preload deviations",
       [](Json& j) { j["s_structure"]["preload_sd"].push_back(0.05); }, "s_structure.preload_sd",
       "expected 8 numbers, got 9", true},
      {"negative preload", [](Json& j) { j["s_structure"]["preload_mean"][3] = -1.221; },
       "s_structure.preload_mean", "element 3", true},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.name);
    Json config = shipped_config();
    c.edit(config);
    std::string path;
    const std::string message = load_error(config, &path);
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_NE(message.find("'" + c.field + "'"), std::string::npos) << message;
    EXPECT_NE(message.find(c.problem), std::string::npos) << message;
    if (c.names_value) {
      // The value as written back by the JSON library (long values are cut).
      const Json* value = &config;
      std::string rest = c.field;
      for (std::size_t dot; (dot = rest.find('.')) != std::string::npos; rest = rest.substr(dot + 1))
        value = &value->at(rest.substr(0, dot));
      const std::string text = value->at(rest).dump().substr(0, 60);
      EXPECT_NE(message.find(text), std::string::npos) << "value " << text << " in: " << message;
    }
  }
}

TEST(RoverConfig, MissingOrMalformedFileNamesTheFile) {
  const std::string dir = testing::temp_dir();
  try {
    io::load_rover_parameters(dir + "/no_such_rover.json");
    ADD_FAILURE() << "a missing file loaded";
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/no_such_rover.json"), std::string::npos) << e.what();
  }
  const std::string broken = dir + "/broken.json";
  std::ofstream(broken) << "{\"gravity\": 9.81,";
  try {
    io::load_rover_parameters(broken);
    ADD_FAILURE() << "a truncated file loaded";
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(broken), std::string::npos) << e.what();
  }
}

TEST(RoverConfig, EditedValuesAreRead) {
  // Not only the defaults: a changed value (and a full inertia tensor) comes through.
  Json config = shipped_config();
  config["bodies"]["module2"]["mass"] = 0.5;
  config["bodies"]["wheel"]["inertia"] = Json::array(
      {Json::array({5e-4, 1e-5, -2e-5}), Json::array({1e-5, 9e-4, 3e-5}), Json::array({-2e-5, 3e-5, 5e-4})});
  config["s_structure"]["preload_mean"][5] = 1.6;
  const std::string path = testing::temp_dir() + "/rover.json";
  std::ofstream(path) << config.dump();
  const RoverParameters p = io::load_rover_parameters(path);
  EXPECT_EQ(p.module2.mass_kg, 0.5);
  EXPECT_EQ(p.wheel.inertia_kgm2(0, 1), 1e-5);
  EXPECT_EQ(p.wheel.inertia_kgm2(2, 1), 3e-5);
  EXPECT_EQ(p.wheel.inertia_kgm2(0, 2), -2e-5);
  EXPECT_EQ(p.s_structure.preload_mean_Nm[5], 1.6);
  EXPECT_EQ(p.s_structure.preload_mean_Nm[4], default_rover_parameters().s_structure.preload_mean_Nm[4]);
}

}  // namespace
}  // namespace rover
