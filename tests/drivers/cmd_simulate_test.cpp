// `rover simulate` and `rover compare` (drivers/cmd_simulate.cpp,
// drivers/cmd_compare.cpp): a short drop writes HDF5, CSV and a PNG plot; a
// file compared with itself (or with its own CSV) has no error; bad options
// fail with a clear message before any run; failed writes are errors; silent
// trouble (a poor friction fit, a chassis ending below the ground) is reported.
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/hdf5_file.hpp"
#include "io/json_reader.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::rover_binary;
using testing::run_command;
using testing::source_path;

// A 0.2 s horizontal drop pointing at the shipped rover and terrain by absolute path.
std::string short_drop_scenario(const std::string& dir) {
  json j = io::read_json_file(source_path("configs/scenarios/drop_horizontal.json"));
  j["name"] = "short_drop";
  j["rover"] = source_path("configs/rover.json");
  j["terrain"] = source_path("configs/terrains/flat.json");
  j["duration"] = 0.2;
  const std::string path = dir + "/short_drop.json";
  std::ofstream(path) << j.dump(2);
  return path;
}

class CmdSimulate : public ::testing::Test {
 protected:
  // One simulation shared by the tests of this suite.
  static void SetUpTestSuite() {
    dir_ = new std::string(testing::temp_dir());
    const std::string scenario = short_drop_scenario(*dir_);
    output_ = new std::string;
    status_ = run_command(rover_binary() + " simulate --scenario " + scenario + " --out " + *dir_ +
                              "/out/drop.h5 --csv " + *dir_ + "/out/drop.csv",
                          output_);
  }
  static void TearDownTestSuite() {
    delete dir_;
    delete output_;
  }
  static std::string* dir_;
  static std::string* output_;
  static int status_;
};
std::string* CmdSimulate::dir_ = nullptr;
std::string* CmdSimulate::output_ = nullptr;
int CmdSimulate::status_ = -1;

TEST_F(CmdSimulate, WritesHdf5CsvAndPng) {
  ASSERT_EQ(status_, 0) << *output_;
  const std::string h5 = *dir_ + "/out/drop.h5", csv = *dir_ + "/out/drop.csv", png = *dir_ + "/out/drop.png";
  ASSERT_TRUE(fs::exists(h5)) << *output_;
  EXPECT_TRUE(fs::exists(csv)) << *output_;
  EXPECT_FALSE(fs::exists(h5 + ".partial"));
  const io::Hdf5Reader reader(h5);
  EXPECT_EQ(reader.shape("/t"), std::vector<std::size_t>{201});  // 0.2 s at 1 kHz, both ends
  EXPECT_EQ(reader.shape("/q"), (std::vector<std::size_t>{201, 23}));
  EXPECT_EQ(reader.attribute_string("/", "status"), "ok");
  EXPECT_GT(reader.attribute_integer("/", "rhs_evaluations"), 0);
  const std::vector<double> bl = reader.read_doubles("/B_l_z");
  EXPECT_LT(bl.back(), bl.front());  // it fell
  // A PNG: the 8-byte signature.
  ASSERT_TRUE(fs::exists(png)) << *output_;
  std::ifstream in(png, std::ios::binary);
  std::string head(8, '\0');
  in.read(head.data(), 8);
  EXPECT_EQ(head, std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_GT(fs::file_size(png), 1000u);
}

TEST_F(CmdSimulate, CompareWithItselfGivesZero) {
  ASSERT_EQ(status_, 0) << *output_;
  const std::string h5 = *dir_ + "/out/drop.h5", csv = *dir_ + "/out/drop.csv";
  for (const std::string& other : {h5, csv}) {
    std::string out;
    ASSERT_EQ(run_command(rover_binary() + " compare " + h5 + " " + other + " --rest-time 0.2", &out), 0) << out;
    const json j = json::parse(out);
    EXPECT_EQ(j.at("rms_m").get<double>(), 0.0) << other;
    EXPECT_EQ(j.at("max_abs_difference_m").get<double>(), 0.0) << other;
    EXPECT_EQ(j.at("deflection_error").get<double>(), 0.0) << other;
    EXPECT_EQ(j.at("at_rest_error").get<double>(), 0.0) << other;
  }
  // Another column is compared when asked; against a shifted curve the RMS is the shift.
  const std::string shifted = *dir_ + "/shifted.csv";
  {
    std::ofstream s(shifted);
    s.precision(17);
    s << "t,z\n";
    const io::Hdf5Reader reader(h5);
    const std::vector<double> t = reader.read_doubles("/t"), g = reader.read_doubles("/G_z");
    for (std::size_t i = 0; i < t.size(); ++i) s << t[i] << "," << g[i] + 0.001 << "\n";
  }
  std::string out;
  ASSERT_EQ(run_command(rover_binary() + " compare " + h5 + " " + shifted + " --column G_z --rest-time 0.1", &out), 0) << out;
  EXPECT_NEAR(json::parse(out).at("rms_m").get<double>(), 0.001, 1e-12);
}

TEST(CmdSimulateOptions, WrongNumberOfPreloadsFailsClearly) {
  const std::string dir = testing::temp_dir();
  const std::string scenario = short_drop_scenario(dir);
  std::string out;
  EXPECT_NE(run_command(rover_binary() + " simulate --scenario " + scenario + " --out " + dir +
                            "/x.h5 --M0 1,1,1,1,1,1,1",
                        &out),
            0);
  EXPECT_NE(out.find("--M0 takes 8 values, got 7"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir + "/x.h5"));
  EXPECT_NE(run_command(rover_binary() + " simulate --scenario " + scenario + " --out " + dir +
                            "/x.h5 --M0 1,1,1,1,1,1,1,1,1",
                        &out),
            0);
  EXPECT_NE(out.find("--M0 takes 8 values"), std::string::npos) << out;
  EXPECT_NE(run_command(rover_binary() + " simulate --scenario " + scenario + " --out " + dir + "/x.h5 --cq -1", &out),
            0);
  EXPECT_NE(out.find("--cq"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir + "/x.h5"));
}

TEST(CmdSimulateOptions, BadScenarioNamesTheFile) {
  const std::string dir = testing::temp_dir();
  json j = io::read_json_file(short_drop_scenario(dir));
  j["integrator"]["method"] = "euler";
  const std::string path = dir + "/bad.json";
  std::ofstream(path) << j.dump();
  std::string out;
  EXPECT_NE(run_command(rover_binary() + " simulate --scenario " + path + " --out " + dir + "/x.h5", &out), 0);
  EXPECT_NE(out.find(path), std::string::npos) << out;
  EXPECT_NE(out.find("'integrator.method'"), std::string::npos) << out;
  EXPECT_NE(out.find("euler"), std::string::npos) << out;
}

// A 0.05 s drop with the stiff integrator; `edit` changes the scenario, and
// `rover_edit` (if given) a copy of the rover config it uses.
std::string quick_scenario(const std::string& dir, const std::function<void(json&)>& edit = {},
                           const std::function<void(json&)>& rover_edit = {}) {
  json j = io::read_json_file(short_drop_scenario(dir));
  j["duration"] = 0.05;
  j["integrator"] = {{"method", "rosenbrock"}};
  if (rover_edit) {
    json rover = io::read_json_file(source_path("configs/rover.json"));
    rover_edit(rover);
    std::ofstream(dir + "/rover.json") << rover.dump();
    j["rover"] = dir + "/rover.json";
  }
  if (edit) edit(j);
  const std::string path = dir + "/quick.json";
  std::ofstream(path) << j.dump();
  return path;
}

TEST(CmdSimulateOptions, NonFiniteAndNegativeFlagsAreRefusedBeforeAnyRun) {
  const std::string dir = testing::temp_dir();
  const std::string base = rover_binary() + " simulate --no-plot --scenario " + quick_scenario(dir) + " --out " + dir + "/x.h5 ";
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"--f inf", {"--f must be a positive finite number, got inf"}},
      {"--f nan --cq inf", {"--f must be a positive finite number, got nan", "--cq must be a finite number >= 0, got inf"}},
      {"--cq -1", {"--cq must be a finite number >= 0, got -1"}},
      {"--f 0 --cq -0.5", {"--f must be", "--cq must be"}},
      {"--M0 1,1,nan,1,1,1,1,1", {"--M0: value 3 must be a finite preload >= 0 N m"}},
      {"--M0 1,1,1,1,1,1,1,-2", {"--M0: value 8", "got -2"}},
      {"--M0 1,1,1,1,inf,1,1,1 --f -inf", {"--M0: value 5", "--f must be"}},
      {"--integrator euler --cq nan", {"--integrator: unknown integrator 'euler'", "--cq must be"}},
  };
  for (const auto& [flags, expected] : cases) {
    std::string out;
    EXPECT_EQ(run_command(base + flags, &out), 1) << flags << out;
    for (const std::string& e : expected) EXPECT_NE(out.find(e), std::string::npos) << flags << "\n" << out;
    EXPECT_EQ(out.find("simulate: quick"), std::string::npos) << "a run started: " << out;
    EXPECT_FALSE(fs::exists(dir + "/x.h5"));
  }
}

TEST(CmdSimulateOptions, FailedWritesAndDirectoriesAreErrors) {
  const std::string dir = testing::temp_dir();
  const std::string scenario = quick_scenario(dir);
  std::string out;
  EXPECT_EQ(run_command(rover_binary() + " simulate --no-plot --scenario " + scenario + " --out " + dir +
                            "/a.h5 --csv /dev/full",
                        &out),
            1);
  EXPECT_NE(out.find("/dev/full: cannot write"), std::string::npos) << out;
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
  for (const std::string& flags : std::vector<std::string>{"--out /dev/full", "--out " + dir, "--out " + dir + "/b.h5 --csv " + dir,
                                   "--out /dev/null"}) {
    EXPECT_EQ(run_command(rover_binary() + " simulate --no-plot --scenario " + scenario + " " + flags, &out), 1)
        << flags;
    EXPECT_TRUE(out.find("is a directory") != std::string::npos ||
                out.find("is not a regular file") != std::string::npos)
        << flags << "\n" << out;
  }
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
  // A scenario path that is a directory.
  EXPECT_NE(run_command(rover_binary() + " simulate --scenario " + dir, &out), 0);
  EXPECT_NE(out.find("directory"), std::string::npos) << out;
}

TEST(CmdSimulateOptions, AbsurdRecordingIsRefusedWithTheEstimate) {
  const std::string dir = testing::temp_dir();
  for (const auto& [key, value] : std::vector<std::pair<std::string, double>>{{"duration", 1e12}, {"output_rate", 1e9}}) {
    const std::string scenario = quick_scenario(dir, [&, k = key, v = value](json& j) {
      if (k == "output_rate") j["duration"] = 1.0;
      j[k] = v;
    });
    std::string out;
    EXPECT_EQ(run_command(rover_binary() + " simulate --scenario " + scenario + " --out " + dir + "/x.h5", &out), 1);
    EXPECT_NE(out.find(key == "duration" ? "would record 1.0e+15 samples (448 PB" : "would record 1.0e+09 samples (448 GB"),
              std::string::npos)
        << out;
    EXPECT_EQ(out.find("bad_alloc"), std::string::npos) << out;
  }
}

TEST(CmdSimulateWarnings, PoorFrictionFitIsReportedAndRecorded) {
  const std::string dir = testing::temp_dir();
  // mu_k six times mu_s: the Makkar curve cannot follow (RMS 0.025 > 0.01).
  const std::string scenario = quick_scenario(dir, {}, [](json& rover) {
    rover["friction"]["mu_s"] = 0.1;
    rover["friction"]["mu_k"] = 0.6;
    rover["friction"].erase("gammas");
    rover["friction"].erase("gammas_fitted_to");
  });
  std::string out;
  ASSERT_EQ(run_command(rover_binary() + " simulate --no-plot --scenario " + scenario + " --out " + dir + "/f.h5", &out), 0) << out;
  EXPECT_NE(out.find("warning: the friction gammas miss the fit quality bar"), std::string::npos) << out;
  const io::Hdf5Reader reader(dir + "/f.h5");
  EXPECT_EQ(reader.attribute_integer("/", "friction_fit_acceptable"), 0);
  EXPECT_GT(reader.attribute_double("/", "friction_fit_rms"), 0.01);
  // The shipped rover: no friction warning, and the file says the fit is acceptable.
  ASSERT_EQ(run_command(rover_binary() + " simulate --no-plot --scenario " + quick_scenario(dir) + " --out " + dir + "/g.h5", &out), 0) << out;
  EXPECT_EQ(out.find("friction gammas"), std::string::npos) << out;
  EXPECT_EQ(io::Hdf5Reader(dir + "/g.h5").attribute_integer("/", "friction_fit_acceptable"), 1);
}

TEST(CmdSimulateWarnings, ChassisGoingThroughTheGroundIsReported) {
  const std::string dir = testing::temp_dir();
  // Ground with almost no stiffness and no damping: the rover falls through it.
  const std::string scenario = quick_scenario(
      dir, [](json& j) { j["duration"] = 0.4; },
      [](json& rover) {
        rover["contact"]["k_g"] = 1.0;
        rover["contact"]["c_g"] = 0.0;
      });
  std::string out;
  ASSERT_EQ(run_command(rover_binary() + " simulate --no-plot --scenario " + scenario + " --out " + dir + "/s.h5", &out), 0) << out;
  EXPECT_NE(out.find("warning: the chassis went through the ground: its origin G reached"), std::string::npos) << out;
  // The ordinary short drop ends on its wheels: no warning.
  ASSERT_EQ(run_command(rover_binary() + " simulate --no-plot --scenario " + quick_scenario(dir) + " --out " + dir + "/t.h5", &out), 0) << out;
  EXPECT_EQ(out.find("through the ground"), std::string::npos) << out;
}

}  // namespace
}  // namespace rover
