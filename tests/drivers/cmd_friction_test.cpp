// `rover friction` (drivers/cmd_friction.cpp): JSON on stdout for the pinned
// config and for changed engineering parameters, and the PNG.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace rover {
namespace {

nlohmann::json run_friction(const std::string& arguments, const std::string& dir) {
  const std::string out = dir + "/out.json";
  std::ostringstream command;  // stdout and stderr to separate files
  command << "(" << testing::rover_binary() << " friction --config "
          << testing::source_path("configs/rover.json") << " " << arguments << " > " << out
          << " 2> " << dir << "/err.txt)";
  EXPECT_EQ(testing::run_command(command.str()), 0)
      << std::ifstream(dir + "/err.txt").rdbuf();
  std::ifstream in(out);
  return nlohmann::json::parse(in);
}

TEST(CmdFriction, KeepsThePinnedGammasOfTheConfig) {
  const std::string dir = testing::temp_dir();
  const nlohmann::json j = run_friction("", dir);
  EXPECT_EQ(j["source"], "config");
  EXPECT_EQ(j["gammas"][0].get<double>(), 0.9264631218718848);
  EXPECT_NEAR(j["quality"]["rms"].get<double>(), 0.00139, 5e-6);
  EXPECT_TRUE(j["quality"]["acceptable"].get<bool>());
  std::filesystem::remove_all(dir);
}

TEST(CmdFriction, SynthesizesForChangedParametersAndPlots) {
  const std::string dir = testing::temp_dir();
  const std::string png = dir + "/plots/friction.png";
  const nlohmann::json j =
      run_friction("--mu-s 0.5 --v-s 1e-3 --mu-k 0.35 --v-k 4e-3 --png " + png, dir);
  EXPECT_EQ(j["source"], "synthesized");
  EXPECT_EQ(j["engineering"]["mu_s"].get<double>(), 0.5);
  EXPECT_TRUE(j["quality"]["acceptable"].get<bool>());
  EXPECT_NEAR(j["quality"]["peak_mu"].get<double>(), 0.5, 0.025);
  std::ifstream in(png, std::ios::binary);
  char signature[4] = {};
  in.read(signature, 4);
  EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  std::filesystem::remove_all(dir);
}

TEST(CmdFriction, RejectsKineticSpeedBelowStaticSpeed) {
  std::string log;
  const std::string command = testing::rover_binary() + " friction --config " +
                              testing::source_path("configs/rover.json") + " --v-k 1e-4";
  EXPECT_NE(testing::run_command(command, &log), 0);
  EXPECT_NE(log.find("v_k"), std::string::npos) << log;
}

TEST(CmdFriction, NonFiniteAndOutOfRangeFlagsAreEachReported) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"--mu-s nan", {"--mu-s must be a finite number >= 0, got nan"}},
      {"--mu-s inf --v-s -1", {"--mu-s must be", "--v-s must be a positive finite number, got -1"}},
      {"--mu-k -0.1 --v-k 0", {"--mu-k must be", "--v-k must be a positive finite number, got 0"}},
      {"--v-s nan --v-k inf", {"--v-s must be", "--v-k must be"}},
  };
  for (const auto& [flags, expected] : cases) {
    std::string out;
    EXPECT_EQ(testing::run_command(testing::rover_binary() + " friction --config " +
                                       testing::source_path("configs/rover.json") + " " + flags,
                                   &out),
              1)
        << flags;
    for (const std::string& e : expected) EXPECT_NE(out.find(e), std::string::npos) << flags << "\n" << out;
    EXPECT_EQ(out.find("\"gammas\""), std::string::npos) << "printed a result: " << out;
  }
}

}  // namespace
}  // namespace rover
