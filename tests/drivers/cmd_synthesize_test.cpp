// `rover synthesize` (drivers/cmd_synthesize.cpp): every bad flag is reported
// on its own line before any simulation, seeds are read as JSON seeds are,
// and a sample count beyond any sane file is refused with its size. Two
// channels of one skewed drop, synthesised at a known damping, are fitted
// jointly by `rover calibrate` and recover it within its 95 % interval.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/csv.hpp"
#include "io/hdf5_file.hpp"
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
      {"--seed -1", {"--seed must be an integer from 0 to 18446744073709551615", "got '-1'"}},
      {"--seed 18446744073709551621", {"--seed must be an integer", "'18446744073709551621'"}},
      {"--seed 2.5 --cq nan --M0 1,1,1,1,1,1,1,-1",
       {"--seed", "--cq must be a finite number >= 0, got nan", "--M0: value 8"}},
      {"--channel pitch --integrator rk5",
       {"--channel: unknown channel 'pitch' (valid: B_l_z, B_r_z, G_z)",
        "--integrator: unknown integrator 'rk5'"}},
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

// The skewed drop's start, 0.5 s with the stiff integrator (data and fit on
// the same integrator, so its error is not mistaken for noise).
std::string short_skewed_scenario(const std::string& dir) {
  nlohmann::json j = io::read_json_file(source_path("configs/scenarios/drop_skewed.json"));
  j["rover"] = source_path("configs/rover.json");
  j["terrain"] = source_path("configs/terrains/flat.json");
  j["duration"] = 0.5;
  j["integrator"] = {{"method", "rosenbrock"}};
  const std::string path = dir + "/skewed.json";
  std::ofstream(path) << j.dump();
  return path;
}

TEST(CmdSynthesize, TwoChannelsOfOneDropFittedJointlyRecoverTheDamping) {
  const std::string dir = testing::temp_dir();
  const std::string scenario = short_skewed_scenario(dir);
  // c_q = 0.3 (not the rover file's 0.25), its own noise sd per channel.
  const std::string base =
      rover_binary() + " synthesize --scenario " + scenario + " --cq 0.3 --offset 0.05 --rate 500 ";
  std::string log;
  ASSERT_EQ(run_command(base + "--channel B_l_z --noise 1e-4 --seed 5 --out " + dir + "/left.csv", &log), 0) << log;
  ASSERT_EQ(run_command(base + "--channel B_r_z --noise 2e-4 --seed 6 --out " + dir + "/right.csv", &log), 0) << log;
  const io::MeasuredCurve left = io::read_measured_curve(dir + "/left.csv");
  const io::MeasuredCurve right = io::read_measured_curve(dir + "/right.csv");
  ASSERT_EQ(left.t_s, right.t_s);
  // The right pin is another curve: it starts 2 cm higher (the roll of the
  // skewed attitude), far beyond the noise.
  double largest_gap = 0.0;
  for (std::size_t i = 0; i < left.z_m.size(); ++i)
    largest_gap = std::max(largest_gap, std::abs(left.z_m[i] - right.z_m[i]));
  EXPECT_GT(largest_gap, 5e-3);
  std::ifstream header(dir + "/right.csv");
  std::string text((std::istreambuf_iterator<char>(header)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("SYNTHETIC"), std::string::npos);
  EXPECT_NE(text.find("B_r_z, the world z of the right bogie pin B_r"), std::string::npos) << text;
  EXPECT_NE(text.find("integrator rosenbrock"), std::string::npos) << text;

  const std::string study = testing::write_file(dir + "/joint.json", R"({"type": "calibration", "name": "j",
      "scenario": ")" + scenario + R"(", "data": [{"file": ")" + dir + R"(/left.csv", "channel": "B_l_z"},
      {"file": ")" + dir + R"(/right.csv", "channel": "B_r_z"}], "fit": ["c_q"],
      "bounds": {"c_q": [0.02, 1.0], "time_offset": [-0.2, 0.2]}, "initial": {"c_q": 0.1}, "max_evaluations": 30})");
  ASSERT_EQ(run_command(rover_binary() + " calibrate --study " + study + " --no-plot --out " + dir + "/joint.h5", &log),
            0) << log;
  const io::Hdf5Reader h5(dir + "/joint.h5");
  // With these seeds the estimate is 1.3 se from the truth (0.29936, se 0.00051,
  // native build); any seed pair misses it about 1 time in 20.
  const double c_q = h5.read_doubles("/best/values").at(0);
  const auto lower = h5.read_doubles("/best/lower"), upper = h5.read_doubles("/best/upper");
  EXPECT_LE(lower.at(0), 0.3) << log;
  EXPECT_GE(upper.at(0), 0.3) << log;
  EXPECT_LT(upper[0] - lower[0], 0.1 * c_q) << log;  // an interval, not the bounds
  // Each curve's own release time and noise level: a mixed-up channel would
  // leave centimetre residuals instead.
  const auto offsets = h5.read_doubles("/best/time_offset"), noise = h5.read_doubles("/best/noise_sd");
  ASSERT_EQ(offsets.size(), 2u);
  EXPECT_NEAR(offsets[0], 0.05, 2e-3);
  EXPECT_NEAR(offsets[1], 0.05, 2e-3);
  EXPECT_NEAR(noise.at(0), 1e-4, 1.5e-5);
  EXPECT_NEAR(noise.at(1), 2e-4, 3e-5);
  EXPECT_NE(h5.read_strings("/data/curves").at(1).find("B_r_z"), std::string::npos);
}

}  // namespace
}  // namespace rover
