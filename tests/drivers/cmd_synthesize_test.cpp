// `rover synthesize` (drivers/cmd_synthesize.cpp): every bad flag is reported
// on its own line before any simulation, seeds are read as JSON seeds are,
// and a sample count beyond any sane file is refused with its size.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/csv.hpp"
#include "io/json_reader.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

namespace fs = std::filesystem;
using testing::rover_binary;
using testing::run_command;
using testing::source_path;

// A 0.05 s horizontal drop with the stiff integrator (a few milliseconds).
std::string short_scenario(const std::string& dir) {
  nlohmann::json j = io::read_json_file(source_path("configs/scenarios/drop_horizontal.json"));
  j["rover"] = source_path("configs/rover.json");
  j["terrain"] = source_path("configs/terrains/flat.json");
  j["duration"] = 0.05;
  j["integrator"] = {{"method", "rosenbrock"}};
  const std::string path = dir + "/short.json";
  std::ofstream(path) << j.dump();
  return path;
}

int count_lines_with(const std::string& text, const std::string& part) {
  int n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

TEST(CmdSynthesize, EveryBadFlagIsReportedBeforeAnyRun) {
  const std::string dir = testing::temp_dir();
  const std::string base = rover_binary() + " synthesize --scenario " + short_scenario(dir) +
                           " --out " + dir + "/curve.csv";
  const struct {
    std::string flags;
    std::vector<std::string> expected;
  } cases[] = {
      {"--rate 0 --noise -1", {"--rate must be a positive finite number, got 0",
                               "--noise must be a finite number >= 0, got -1"}},
      {"--rate nan --offset inf --f -3", {"--rate", "--offset must be a finite number, got inf",
                                          "--f must be a positive finite number, got -3"}},
      {"--seed -1", {"--seed must be an integer from 0 to 18446744073709551615, got '-1'"}},
      {"--seed 18446744073709551621", {"--seed must be an integer", "'18446744073709551621'"}},
      {"--seed 2.5 --cq nan --M0 1,1,1,1,1,1,1,-1",
       {"--seed", "--cq must be a finite number >= 0, got nan", "--M0: value 8"}},
  };
  for (const auto& c : cases) {
    std::string out;
    EXPECT_NE(run_command(base + " " + c.flags, &out), 0) << c.flags;
    for (const std::string& e : c.expected) EXPECT_NE(out.find(e), std::string::npos) << c.flags << "\n" << out;
    // One line per bad flag.
    EXPECT_EQ(count_lines_with(out, "rover synthesize: error: "), count_lines_with(c.flags, "--")) << out;
    EXPECT_FALSE(fs::exists(dir + "/curve.csv"));
  }
}

TEST(CmdSynthesize, SeedsAcceptWhatTheJsonSeedAccepts) {
  const std::string dir = testing::temp_dir();
  const std::string base = rover_binary() + " synthesize --scenario " + short_scenario(dir) + " --out ";
  // The largest seed and a seed written as 1e3 are seeds; both files are valid curves.
  for (const std::string seed : {"18446744073709551615", "1e3"}) {
    const std::string path = dir + "/seed.csv";
    std::string out;
    ASSERT_EQ(run_command(base + path + " --seed " + seed, &out), 0) << out;
    EXPECT_EQ(io::read_measured_curve(path).t_s.size(), 26u);  // 0.05 s at 500 Hz, both ends
  }
}

TEST(CmdSynthesize, AbsurdRatesAreRefusedWithTheSize) {
  const std::string dir = testing::temp_dir();
  std::string out;
  // The default scenario: 1 s at 1 GHz would be 1e9 lines of about 50 bytes.
  EXPECT_NE(run_command(rover_binary() + " synthesize --scenario " +
                            source_path("configs/scenarios/drop_horizontal.json") + " --rate 1e9 --out " +
                            dir + "/big.csv",
                        &out),
            0);
  EXPECT_NE(out.find("would record 1.0e+09 samples (50 GB"), std::string::npos) << out;
  EXPECT_NE(out.find("reduce --rate"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir + "/big.csv"));
  // An output path that is a directory.
  EXPECT_NE(run_command(rover_binary() + " synthesize --scenario " + short_scenario(dir) + " --out " + dir, &out), 0);
  EXPECT_NE(out.find("--out '" + dir + "' is a directory"), std::string::npos) << out;
}

}  // namespace
}  // namespace rover
