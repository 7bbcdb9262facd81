// `rover kinematics` (drivers/cmd_kinematics.cpp): the printed wheel commands
// are those of the library for the same config, and bad commands fail with a
// message that names the problem.
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/drive_kinematics.hpp"
#include "io/rover_config.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using rover::testing::rover_binary;
using rover::testing::run_command;
using rover::testing::source_path;

std::string kinematics(const std::string& args) {
  return rover_binary() + " kinematics --config " + source_path("configs/rover.json") + " " + args;
}

TEST(CmdKinematics, JsonMatchesTheLibrary) {
  const DriveKinematics kin =
      make_drive_kinematics(io::load_rover_parameters(source_path("configs/rover.json")));
  struct Case {
    std::string args;
    DriveCommand command;
  };
  const Case cases[] = {
      {"--mode ackermann --v 0.5 --radius 1.0", symmetric_ackermann_command(kin, 0.5, 1.0)},
      {"--mode car --v -0.3 --radius -0.8", car_like_command(kin, -0.3, -0.8)},
      {"--mode general-ackermann --v 0.2 --icr-x 0.3 --icr-y -0.6",
       general_ackermann_command(0.2, Vec2(0.3, -0.6))},
      {"--mode parallel --v 0.2 --crab-deg 30", parallel_command(0.2, std::numbers::pi / 6)},
      {"--mode lateral --v -0.1", lateral_command(-0.1)},
      {"--mode rotation --yaw-rate 0.5", in_place_rotation_command(0.5)},
      {"--mode general-ackermann --vx 0.3 --vy 0.1 --yaw-rate 0.2",
       drive_command(kin, DriveMode::kGeneralAckermann, {0.3, 0.1, 0.2})}};
  for (const Case& c : cases) {
    std::string out;
    ASSERT_EQ(run_command(kinematics(c.args + " --json"), &out), 0) << c.args << "\n" << out;
    const nlohmann::json j = nlohmann::json::parse(out);
    const WheelCommands expected = wheel_commands(kin, c.command);
    ASSERT_EQ(j.at("wheels").size(), 4u);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const nlohmann::json& w = j.at("wheels")[leg];
      EXPECT_EQ(w.at("name").get<std::string>(), kWheelNames[leg]);
      EXPECT_NEAR(w.at("steer_rad").get<double>(), expected.steer_rad[leg], 1e-12) << c.args;
      EXPECT_NEAR(w.at("steer_deg").get<double>(), expected.steer_rad[leg] * 180 / std::numbers::pi,
                  1e-9);
      EXPECT_NEAR(w.at("wheel_speed_radps").get<double>(), expected.wheel_speed_radps[leg], 1e-12)
          << c.args;
      EXPECT_EQ(w.at("flipped").get<bool>(), expected.flipped[leg]);
    }
  }
}

TEST(CmdKinematics, TablePrintsEveryWheel) {
  std::string out;
  ASSERT_EQ(run_command(kinematics("--mode ackermann --v 0.5 --radius 1.0"), &out), 0) << out;
  for (const char* name : kWheelNames) EXPECT_NE(out.find(std::string(name) + " "), std::string::npos) << out;
  EXPECT_NE(out.find("ICR (0.0000, 1.0000) m"), std::string::npos) << out;
}

TEST(CmdKinematics, BadCommandsFailWithAMessage) {
  const std::pair<const char*, const char*> cases[] = {
      {"--mode ackermann --v 0.3 --radius 0.1 --no-flip", "FL needs a steering angle"},
      {"--mode car --vx 0.5 --vy 0.2", "rear-axle centre"},
      {"--mode parallel --v 0.3 --radius 1", "--radius is not a parameter of the parallel mode"},
      {"--mode ackermann --v 0.3 --vx 0.3", "cannot be combined"},
      {"--mode general-ackermann --v 0.3", "needs --icr-x"},
      {"--mode flying --v 1", "flying"}};
  for (const auto& [args, needle] : cases) {
    std::string out;
    EXPECT_NE(run_command(kinematics(args), &out), 0) << args;
    EXPECT_NE(out.find(needle), std::string::npos) << args << "\n" << out;
  }
}

TEST(CmdKinematics, NonFiniteNumbersAreRefusedByFlag) {
  for (const std::string flags :
       {"--mode car --v inf", "--mode ackermann --v 0.5 --radius nan", "--mode parallel --v 0.2 --crab-deg inf",
        "--mode rotation --yaw-rate -inf", "--mode general-ackermann --v 0.1 --icr-x nan --icr-y 1",
        "--mode lateral --vy nan"}) {
    std::string out;
    EXPECT_EQ(testing::run_command(testing::rover_binary() + " kinematics --config " +
                                       testing::source_path("configs/rover.json") + " " + flags,
                                   &out),
              1)
        << flags;
    EXPECT_NE(out.find("must be a finite number"), std::string::npos) << flags << "\n" << out;
  }
}

}  // namespace
}  // namespace rover
