// `rover terrain obstacle` (drivers/cmd_terrain.cpp): each bad flag is named
// with its value before anything is written, and an output path that is a
// directory is refused.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace rover {
namespace {

TEST(CmdTerrain, BadFlagsAreEachNamed) {
  const std::string dir = testing::temp_dir();
  const std::string base = testing::rover_binary() + " terrain obstacle --out " + dir + "/t.json ";
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"--spacing 0", {"--spacing must be a positive finite number, got 0"}},
      {"--spacing nan --margin -1", {"--spacing must be", "--margin must be a finite number >= 0, got -1"}},
      {"--height inf --ramp-angle-deg 90", {"--height must be", "--ramp-angle-deg must lie in (0, 90), got 90"}},
      {"--foot-x nan --top-length -0.1", {"--foot-x must be a finite number", "--top-length must be"}},
      {"--y-min 0.2 --y-max 0.1", {"--y-min (0.2) must be below --y-max (0.1)"}},
      {"--ramp-angle-deg nan", {"--ramp-angle-deg must lie in (0, 90), got nan"}},
  };
  for (const auto& [flags, expected] : cases) {
    std::string out;
    EXPECT_EQ(testing::run_command(base + flags, &out), 1) << flags;
    for (const std::string& e : expected) EXPECT_NE(out.find(e), std::string::npos) << flags << "\n" << out;
    EXPECT_FALSE(std::filesystem::exists(dir + "/t.json")) << flags;
  }
  std::string out;
  EXPECT_EQ(testing::run_command(testing::rover_binary() + " terrain obstacle --out " + dir, &out), 1);
  EXPECT_NE(out.find("--out '" + dir + "' is a directory"), std::string::npos) << out;
  // Control: a coarse obstacle is written.
  EXPECT_EQ(testing::run_command(base + "--spacing 0.01", &out), 0) << out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/t.json"));
}

}  // namespace
}  // namespace rover
