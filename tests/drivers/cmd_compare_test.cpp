// `rover compare` (drivers/cmd_compare.cpp): measured CSV curves are checked
// as read_measured_curve checks them, and a metric that is not finite is an
// error naming it instead of JSON null.
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_support.hpp"

namespace rover {
namespace {

using testing::rover_binary;
using testing::run_command;

std::string write_curve(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(CmdCompare, UndefinedMetricsAreErrorsNamingTheReference) {
  const std::string dir = testing::temp_dir();
  const std::string drop = write_curve(dir, "drop.csv", "t,z\n0,0.2\n0.1,0.15\n0.2,0.18\n0.3,0.19\n");
  // A flat reference: eq. 10 divides by z_r,ref - z_min,ref = 0.
  const std::string flat = write_curve(dir, "flat.csv", "t,z\n0,0.2\n0.1,0.2\n0.2,0.2\n0.3,0.2\n");
  // A reference at rest on z = 0: eq. 11 divides by z_ref(t_rest) = 0.
  const std::string zero = write_curve(dir, "zero.csv", "t,z\n0,0.1\n0.1,-0.1\n0.2,0\n0.3,0\n");
  const struct {
    std::string a, b, metric;
  } cases[] = {{drop, flat, "deflection_error"}, {flat, flat, "deflection_error"}, {drop, zero, "at_rest_error"}};
  for (const auto& c : cases) {
    std::string out;
    EXPECT_EQ(run_command(rover_binary() + " compare " + c.a + " " + c.b + " --rest-time 0.25", &out), 1) << out;
    EXPECT_NE(out.find("rover compare: error: " + c.metric + " (eq. 1"), std::string::npos) << out;
    EXPECT_NE(out.find("is undefined: curve B ('" + c.b + "'"), std::string::npos) << out;
    EXPECT_NE(out.find("--rest-time 0.25 s"), std::string::npos) << out;
    EXPECT_EQ(out.find("null"), std::string::npos) << out;
  }
  // Control: a proper reference gives finite numbers and exit 0.
  std::string out;
  ASSERT_EQ(run_command(rover_binary() + " compare " + drop + " " + drop + " --rest-time 0.25", &out), 0) << out;
  EXPECT_EQ(nlohmann::json::parse(out).at("deflection_error").get<double>(), 0.0);
}

TEST(CmdCompare, BadCurvesAndFlagsAreNamed) {
  const std::string dir = testing::temp_dir();
  const std::string good = write_curve(dir, "good.csv", "t,z\n0,0.2\n0.1,0.15\n0.2,0.18\n");
  const std::vector<std::pair<std::string, std::string>> curves = {
      {"t,z\n0,0.2\n0.1,0.15\n0.1,0.18\n", ":4: column 't'"},
      {"\xEF\xBB\xBFt,z\n0,0.2\n0.2,0.15\n0.1,0.18\n", ":4: column 't'"},
      {"t,z\n0,0.2\n0.1,1500\n0.2,0.18\n", ":3: column 'z'"},
      {"t,z\n0,0.2\n0.1,0.2\n", ": 2 data row(s); a curve needs at least 3"},
  };
  for (const auto& [text, where] : curves) {
    const std::string bad = write_curve(dir, "bad.csv", text);
    std::string out;
    EXPECT_EQ(run_command(rover_binary() + " compare " + good + " " + bad, &out), 1) << out;
    EXPECT_NE(out.find(bad + where), std::string::npos) << out;
  }
  for (const std::string flags : {"--rest-time nan", "--time-offset inf", "--rest-time -inf --time-offset nan"}) {
    std::string out;
    EXPECT_EQ(run_command(rover_binary() + " compare " + good + " " + good + " " + flags, &out), 1) << flags;
    EXPECT_NE(out.find("must be a finite number"), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace rover
