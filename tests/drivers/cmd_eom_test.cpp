// `rover eom` (drivers/cmd_eom.cpp): the printed M, F, points and contacts are
// those of the library (compute_dynamics) at the same state,
// "params" overrides act on the right entries of F only, and a bad state file
// fails with a message naming the file and the field.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/equations_of_motion.hpp"
#include "io/model_config.hpp"
#include "io/scenario_config.hpp"
#include "model_fixtures.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using nlohmann::json;
using testing::rover_binary;
using testing::run_command;
using testing::source_path;

json to_json(const Coordinates& v) {
  json a = json::array();
  for (int i = 0; i < kNumCoordinates; ++i) a.push_back(v[i]);
  return a;
}

std::string write_state(const std::string& dir, const json& state) {
  const std::string path = dir + "/state.json";
  std::ofstream(path) << state.dump(2);
  return path;
}

// Runs `rover eom` and parses its output; fails the test on a non-zero exit.
json run_eom(const std::string& state_path, const std::string& extra = "") {
  std::string out;
  const int status = run_command(rover_binary() + " eom --config " + source_path("configs/rover.json") +
                                     " --state " + state_path + " " + extra,
                                 &out);
  EXPECT_EQ(status, 0) << out;
  try {
    return json::parse(out);
  } catch (const json::exception& e) {
    ADD_FAILURE() << "output is not JSON (" << e.what() << "):\n" << out;
    return json::object();
  }
}

double max_abs(const Eigen::Ref<const Eigen::MatrixXd>& m) { return m.cwiseAbs().maxCoeff(); }

// A state with some wheels in the ground and everything moving: the deepest
// wheel 2 cm in (rover eom refuses a wheel buried deeper than its radius).
void ground_state(Coordinates& q, Coordinates& u, unsigned seed) {
  constexpr double kDeepestPenetration_m = 0.02;
  std::mt19937 rng(seed);
  testing::random_state(rng, q, u);
  q[coord::z] = 0.21;
  const RoverModel model = io::load_rover_model(source_path("configs/rover.json"));
  q[coord::z] += io::deepest_wheel_penetration(model, q).depth_m - kDeepestPenetration_m;
}

void expect_vector(const json& a, const Eigen::Ref<const Eigen::VectorXd>& expected, double tol,
                   const std::string& what) {
  ASSERT_TRUE(a.is_array()) << what;
  ASSERT_EQ(a.size(), static_cast<std::size_t>(expected.size())) << what;
  const double scale = std::max(1.0, max_abs(expected));
  for (Eigen::Index i = 0; i < expected.size(); ++i)
    EXPECT_NEAR(a[i].get<double>(), expected[i], tol * scale) << what << "[" << i << "]";
}

TEST(CmdEom, OutputMatchesTheLibrary) {
  Coordinates q, u;
  ground_state(q, u, 11);
  const std::string dir = testing::temp_dir();
  const json out = run_eom(write_state(dir, {{"q", to_json(q)}, {"u", to_json(u)}}));

  const RoverModel model = io::load_rover_model(source_path("configs/rover.json"));
  const ModelInputs inputs = nominal_inputs(model.parameters);
  DynamicsWorkspace eom;
  compute_dynamics(model, eom, inputs, q, u);
  const TreeKinematics& kin = eom.kinematics;

  // M: 23 x 23, relative 1e-12 of its largest entry.
  ASSERT_EQ(out.at("M").size(), 23u);
  const double m_scale = max_abs(eom.mass_matrix);
  for (int r = 0; r < kNumCoordinates; ++r) {
    ASSERT_EQ(out["M"][r].size(), 23u);
    for (int c = 0; c < kNumCoordinates; ++c)
      EXPECT_NEAR(out["M"][r][c].get<double>(), eom.mass_matrix(r, c), 1e-12 * m_scale) << r << "," << c;
  }
  expect_vector(out.at("F"), eom.forcing, 1e-12, "F");
  expect_vector(out.at("F_nocontact"), eom.forcing_without_contact, 1e-12, "F_nocontact");

  const json& points = out.at("points");
  expect_vector(points.at("B_l"), kin.nodes[node::bogie_left].origin, 1e-12, "B_l");
  expect_vector(points.at("B_r"), kin.nodes[node::bogie_right].origin, 1e-12, "B_r");
  expect_vector(points.at("G"), kin.nodes[node::chassis].origin, 1e-12, "G");
  ASSERT_EQ(points.at("wheel_centres").size(), 4u);
  for (int leg = 0; leg < kNumLegs; ++leg)
    expect_vector(points["wheel_centres"][leg], kin.nodes[node::wheel(leg)].origin, 1e-12, "wheel centre");

  // Contacts, per wheel; this state has some.
  ASSERT_EQ(out.at("contacts").size(), 4u);
  int touching = 0;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const json& wheel = out["contacts"][leg];
    ASSERT_EQ(wheel.size(), static_cast<std::size_t>(eom.contacts[leg].count)) << "leg " << leg;
    for (int k = 0; k < eom.contacts[leg].count; ++k) {
      const ContactPoint& c = eom.contacts[leg].points[k];
      expect_vector(wheel[k].at("point"), c.point_m, 1e-12, "contact point");
      expect_vector(wheel[k].at("normal"), c.normal, 1e-12, "contact normal");
      expect_vector(wheel[k].at("Ft"), c.friction_force_N, 1e-12, "Ft");
      EXPECT_NEAR(wheel[k].at("penetration").get<double>(), c.penetration_m, 1e-15);
      EXPECT_NEAR(wheel[k].at("Fn").get<double>(), c.normal_force_N, 1e-12 * std::max(1.0, c.normal_force_N));
      ++touching;
    }
  }
  EXPECT_GT(touching, 0);
  // The contact part of F is what the contacts make it: F - F_nocontact = sum J^T f.
  const Coordinates contact_part = contact_generalized_forces(model, kin, eom.contacts);
  expect_vector(out["F"], eom.forcing_without_contact + contact_part, 1e-12, "F = F_nocontact + Q_contact");
}

TEST(CmdEom, TerrainOptionUsesTheTerrain) {
  // On the obstacle, a wheel over the ramp feels the ramp: the library agrees.
  Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
  // Front-right wheel centre 0.1 m past the ramp foot, 1 mm into the 20 deg ramp.
  const double ramp = 20.0 * M_PI / 180.0, R = 0.085, x_c = 1.36 + 0.1;
  q[coord::x] = x_c - 0.360;
  q[coord::y] = 0.0;
  q[coord::z] = (R - 0.001) / std::cos(ramp) + (x_c - 1.36) * std::tan(ramp) + 0.1435;
  const std::string terrain = source_path("configs/terrains/obstacle.json");
  const json out = run_eom(write_state(testing::temp_dir(), {{"q", to_json(q)}, {"u", to_json(u)}}),
                           "--terrain " + terrain);
  const RoverModel model = io::load_rover_model(source_path("configs/rover.json"), terrain);
  DynamicsWorkspace eom;
  compute_dynamics(model, eom, nominal_inputs(model.parameters), q, u);
  expect_vector(out.at("F"), eom.forcing, 1e-12, "F");
  const int front_right = 1;
  ASSERT_EQ(out["contacts"][front_right].size(), 1u) << out["contacts"].dump();
  EXPECT_EQ(eom.contacts[front_right].count, 1);
  const json& c = out["contacts"][front_right][0];
  EXPECT_NEAR(c["normal"][0].get<double>(), -std::sin(ramp), 1e-6);
  EXPECT_NEAR(c["normal"][2].get<double>(), std::cos(ramp), 1e-6);
  EXPECT_NEAR(c["penetration"].get<double>(), 0.001, 1e-8);
  for (int leg : {0, 2, 3}) EXPECT_EQ(out["contacts"][leg].size(), 0u) << "leg " << leg;
}

TEST(CmdEom, ParamsOverridesChangeOnlyTheirEntries) {
  Coordinates q, u;
  ground_state(q, u, 12);
  const std::string dir = testing::temp_dir();
  const json base = run_eom(write_state(dir, {{"q", to_json(q)}, {"u", to_json(u)}}));
  auto F_of = [](const json& out, const char* key) {
    Coordinates F;
    for (int i = 0; i < kNumCoordinates; ++i) F[i] = out.at(key)[i].get<double>();
    return F;
  };
  const Coordinates F0 = F_of(base, "F"), F0_nc = F_of(base, "F_nocontact");
  const double c_q0 = default_rover_parameters().s_structure.damping_c_q, c_q1 = 0.5;

  // c_q: only the S-joint entries change, by -(c_q1 - c_q0) * rate.
  const json damped = run_eom(
      write_state(dir, {{"q", to_json(q)}, {"u", to_json(u)}, {"params", {{"c_q", c_q1}}}}));
  const Coordinates dF = F_of(damped, "F") - F0;
  for (int i = 0; i < kNumCoordinates; ++i) {
    const bool s_joint = i >= coord::s_joint(0, 0) && i <= coord::s_joint(3, 1);
    const double expected = s_joint ? -(c_q1 - c_q0) * u[i] : 0.0;
    EXPECT_NEAR(dF[i], expected, 1e-12 * std::max(1.0, std::abs(F0[i]))) << kCoordinateNames[i];
  }
  EXPECT_EQ(F_of(damped, "F") - F_of(damped, "F_nocontact"), F0 - F0_nc);  // contacts untouched
  EXPECT_EQ(damped["M"], base["M"]);

  // w_ref: only the wheel drive entries change, as the drive law says.
  const std::array<double, 4> w_ref{1.0, -2.0, 0.5, 3.0};
  const json driven = run_eom(
      write_state(dir, {{"q", to_json(q)}, {"u", to_json(u)}, {"params", {{"w_ref", w_ref}}}}));
  const Coordinates dFw = F_of(driven, "F") - F0;
  const DriveParameters drive = default_rover_parameters().drive;
  for (int i = 0; i < kNumCoordinates; ++i) {
    double expected = 0.0;
    for (int leg = 0; leg < kNumLegs; ++leg)
      if (i == coord::spin(leg))
        expected = drive.max_torque_Nm * (std::tanh(-drive.gain_Nms_per_rad * (u[i] - w_ref[leg]) / drive.max_torque_Nm) -
                                          std::tanh(-drive.gain_Nms_per_rad * u[i] / drive.max_torque_Nm));
    EXPECT_NEAR(dFw[i], expected, 1e-12 * std::max(1.0, std::abs(F0[i]))) << kCoordinateNames[i];
  }
}

TEST(CmdEom, BadStateFilesNameFileAndField) {
  Coordinates q = Coordinates::Zero(), u = Coordinates::Zero();
  q[coord::z] = 0.3;
  json short_q = to_json(q);
  short_q.erase(22);
  const struct {
    const char* name;
    json state;
    std::string needle;
  } cases[] = {
      {"22 coordinates", {{"q", short_q}, {"u", to_json(u)}}, "'q' (value"},
      {"missing u", {{"q", to_json(q)}}, "'u'"},
      {"unknown key", {{"q", to_json(q)}, {"u", to_json(u)}, {"qdot", to_json(u)}}, "'qdot'"},
      {"unknown params key",
       {{"q", to_json(q)}, {"u", to_json(u)}, {"params", {{"cq", 0.2}}}},
       "'params.cq'"},
      {"7 preloads",
       {{"q", to_json(q)}, {"u", to_json(u)}, {"params", {{"M0", {1, 1, 1, 1, 1, 1, 1}}}}},
       "'params.M0'"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = write_state(testing::temp_dir(), c.state);
    std::string out;
    EXPECT_NE(run_command(rover_binary() + " eom --config " + source_path("configs/rover.json") +
                              " --state " + path,
                          &out),
              0);
    EXPECT_NE(out.find(path), std::string::npos) << out;
    EXPECT_NE(out.find(c.needle), std::string::npos) << out;
  }
  // Wrong length says how many numbers it wanted.
  const std::string path = write_state(testing::temp_dir(), {{"q", short_q}, {"u", to_json(u)}});
  std::string out;
  run_command(rover_binary() + " eom --config " + source_path("configs/rover.json") + " --state " + path, &out);
  EXPECT_NE(out.find("expected 23 numbers, got 22"), std::string::npos) << out;
}

TEST(CmdEom, NonFiniteResultsAreErrorsNamingTheQuantity) {
  const std::string dir = testing::temp_dir();
  Coordinates q, u;
  ground_state(q, u, 5);
  // An S-joint angle of 1e308 rad, which would overflow its spring torque
  // k_q b, is refused before F is computed: beyond a quarter turn.
  for (const double angle : {1e308, -1e308}) {
    Coordinates bent = q;
    bent[coord::s_joint(0, 0)] = angle;
    std::string out;
    EXPECT_EQ(run_command(rover_binary() + " eom --config " + source_path("configs/rover.json") + " --state " +
                              write_state(dir, {{"q", to_json(bent)}, {"u", to_json(u)}}),
                          &out),
              1)
        << out;
    EXPECT_NE(out.find(angle > 0 ? "b11 = 1e+308 rad is beyond" : "b11 = -1e+308 rad is beyond"), std::string::npos) << out;
    EXPECT_EQ(out.find("null"), std::string::npos) << out;
  }
}

TEST(CmdEom, DefaultConfigIsFoundFromAnotherDirectoryOrExplained) {
  const std::string dir = testing::temp_dir();
  Coordinates q, u;
  ground_state(q, u, 7);
  const std::string state = write_state(dir, {{"q", to_json(q)}, {"u", to_json(u)}});
  std::string out;
  // From another directory: the repository of the binary supplies configs/rover.json.
  ASSERT_EQ(run_command("cd " + dir + " && " + rover_binary() + " eom --state " + state, &out), 0) << out;
  const json printed = json::parse(out);
  const json reference = run_eom(state);  // with --config given
  EXPECT_EQ(printed.at("F"), reference.at("F"));
  // A copy of the program outside any repository: the message says how to pass the file.
  const std::string copy = dir + "/rover";
  std::filesystem::copy_file(rover_binary(), copy);
  std::filesystem::permissions(copy, std::filesystem::perms::owner_exec, std::filesystem::perm_options::add);
  for (const std::string& command : std::vector<std::string>{"eom --state " + state, "friction",
                                                            "kinematics --mode rotation --yaw-rate 1"}) {
    EXPECT_EQ(run_command("cd " + dir + " && (./rover " + command + " > /dev/null)", &out), 1) << command;
    EXPECT_NE(out.find("the default --config configs/rover.json exists neither"), std::string::npos) << out;
    EXPECT_NE(out.find("pass --config FILE"), std::string::npos) << out;
  }
}

TEST(CmdEom, OutputToAFullDeviceFails) {
  const std::string dir = testing::temp_dir();
  Coordinates q, u;
  ground_state(q, u, 3);
  const std::string command = rover_binary() + " eom --config " + source_path("configs/rover.json") +
                              " --state " + write_state(dir, {{"q", to_json(q)}, {"u", to_json(u)}});
  std::string out;
  EXPECT_EQ(run_command(command + " > /dev/null", &out), 0) << out;
  EXPECT_EQ(run_command("(" + command + " > /dev/full)", &out), 1);  // stderr still captured
  EXPECT_NE(out.find("rover eom: error: cannot write to standard output"), std::string::npos) << out;
}

}  // namespace
}  // namespace rover
