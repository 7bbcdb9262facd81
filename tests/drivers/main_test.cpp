// The `rover` program's entry point (drivers/main.cpp): a mistyped subcommand
// gets the nearest name, every bad flag of a command line is reported on its
// own line, and output that cannot be written (a full disk) is an error.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace rover {
namespace {

using testing::rover_binary;
using testing::run_command;
using testing::source_path;

TEST(RoverMain, MistypedSubcommandSuggestsTheNearest) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"simulat", "simulate"},     {"simualte", "simulate"},   {"smulate", "simulate"},
      {"compre", "compare"},       {"montecralo", "montecarlo"}, {"eomm", "eom"},
      {"kinematic", "kinematics"}, {"frcition", "friction"},   {"synthesise", "synthesize"},
      {"terain", "terrain"},       {"calibrat", "calibrate"},  {"surfac", "surface"},
  };
  for (const auto& [typed, meant] : cases) {
    std::string out;
    EXPECT_NE(run_command(rover_binary() + " " + typed + " --help", &out), 0) << typed;
    EXPECT_NE(out.find("unknown subcommand '" + typed + "'; did you mean '" + meant + "'?"),
              std::string::npos)
        << out;
  }
  // Nothing near: the list instead of a guess.
  std::string out;
  EXPECT_NE(run_command(rover_binary() + " xyzzyplugh", &out), 0);
  EXPECT_EQ(out.find("did you mean"), std::string::npos) << out;
  EXPECT_NE(out.find("subcommands: eom, friction"), std::string::npos) << out;
  // The right names still run.
  EXPECT_EQ(run_command(rover_binary() + " simulate --help", &out), 0) << out;
}

TEST(RoverMain, OutputToAFullDeviceFails) {
  const std::vector<std::string> commands = {
      " kinematics --mode rotation --yaw-rate 0.5 --config " + source_path("configs/rover.json"),
      " kinematics --mode ackermann --v 0.5 --radius 1 --json --config " +
          source_path("configs/rover.json"),
      " friction --config " + source_path("configs/rover.json"),
  };
  for (const std::string& command : commands) {
    std::string out;
    // Control: the same command succeeds when stdout can take it.
    EXPECT_EQ(run_command(rover_binary() + command + " > /dev/null", &out), 0) << command << out;
    // (stdout to the device inside the subshell; its stderr is captured)
    std::string to_full = "(";
    to_full += rover_binary() + command + " > /dev/full)";
    EXPECT_NE(run_command(to_full, &out), 0) << command;
    EXPECT_NE(out.find("cannot write to standard output"), std::string::npos) << command << out;
  }
}

}  // namespace
}  // namespace rover
