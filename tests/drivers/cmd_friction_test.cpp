// `rover friction` (drivers/cmd_friction.cpp): JSON on stdout for the pinned
// config and for changed engineering parameters, and the PNG.
#include <filesystem>
#include <fstream>
#include <sstream>

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

}  // namespace
}  // namespace rover
