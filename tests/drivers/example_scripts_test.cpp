// The documentation's example scripts run as written: docs/examples/*.py,
// shown verbatim in docs/studies.md. A script whose Python module is not
// installed is skipped with a message.
#include <cstdio>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace rover {
namespace {

using rover::testing::read_file;
using rover::testing::rover_binary;
using rover::testing::run_command;
using rover::testing::source_path;

// OpenTURNS draws a pick-freeze design over (c_q, f), `rover evaluate` runs
// it, OpenTURNS estimates the indices of the peak compression: the damping
// dominates it over these ranges, and every index is a share of a variance.
TEST(ExampleScripts, OpenTurnsDrivesEvaluate) {
  const std::string script = source_path("docs/examples/evaluate_openturns.py");
  EXPECT_NE(read_file(source_path("docs/studies.md")).find(read_file(script)), std::string::npos)
      << "docs/studies.md must show " << script << " as it is";
  if (run_command("/usr/bin/python3 -c 'import openturns'") != 0)
    GTEST_SKIP() << "python3-openturns is not installed (apt-get install python3-openturns)";
  const std::string dir = rover::testing::temp_dir();
  std::string log;
  ASSERT_EQ(run_command("cd " + dir + " && /usr/bin/python3 " + script + " " + rover_binary(), &log), 0) << log;
  double s1_cq = -1, st_cq = -1, s1_f = -1, st_f = -1;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    std::sscanf(line.c_str(), "B_l_z_min: c_q S1 %lf ST %lf", &s1_cq, &st_cq);
    std::sscanf(line.c_str(), "B_l_z_min: f S1 %lf ST %lf", &s1_f, &st_f);
  }
  for (double index : {s1_cq, st_cq, s1_f, st_f}) {
    EXPECT_GT(index, -0.1) << log;
    EXPECT_LT(index, 1.1) << log;
  }
  EXPECT_GT(s1_cq, 2 * s1_f) << log;
}

}  // namespace
}  // namespace rover
