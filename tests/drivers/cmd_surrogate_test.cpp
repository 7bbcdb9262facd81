// `rover surrogate` end to end through the built program: a design trained on
// two ranks and its saved model predicting a design CSV; a surrogate trained
// on a Monte Carlo result file that reproduces its QoI means and sds; and the
// command lines it refuses.
#include <cmath>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "io/csv.hpp"
#include "io/hdf5_file.hpp"
#include "study/estimators/test_models.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using rover::testing::mpiexec;
using rover::testing::rover_binary;
using rover::testing::run_command;
using rover::testing::write_file;

std::string surrogate(const std::string& arguments) {
  return rover_binary() + " surrogate " + arguments;
}

TEST(CmdSurrogate, TrainsOnTwoRanksAndPredictsADesignCsv) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = write_file(dir + "/ish.json", R"({"type": "surrogate", "name": "ish", "model": "ishigami",
      "design": {"type": "lhs", "samples": 400, "seed": 3}, "held_out": {"fraction": 0.1},
      "pce": {"max_degree": 14, "bootstrap": 20}})");
  std::string log;
  ASSERT_EQ(run_command(mpiexec() + " -np 2 " + rover_binary() + " surrogate --study " + study + " --no-plot --out " +
                            dir + "/ish.h5",
                        &log),
            0)
      << log;
  EXPECT_NE(log.find("y: PCE degree"), std::string::npos) << log;
  EXPECT_NE(log.find("held-out Q2"), std::string::npos) << log;
  const io::Hdf5Reader h5(dir + "/ish.h5");
  EXPECT_EQ(h5.attribute_integer("/surrogate/models/y", "test_points"), 40);
  EXPECT_GT(h5.attribute_double("/surrogate/models/y", "q2_test"), 0.99);
  EXPECT_EQ(h5.attribute_string("/", "surrogate"), "pce");
  EXPECT_EQ(h5.read_doubles("/indices/y/ST").size(), 3u);
  EXPECT_FALSE(std::ifstream(dir + "/ish.h5.checkpoint").good());

  write_file(dir + "/x.csv", "x1,x2,x3\n0.5,-1,2\n-2,0.3,0.1\n");
  ASSERT_EQ(run_command(rover_binary() + " surrogate --predict " + dir + "/ish.h5 --design " + dir +
                            "/x.csv --csv " + dir + "/y.csv",
                        &log),
            0)
      << log;
  EXPECT_NE(log.find("us per point"), std::string::npos) << log;
  const io::CsvTable y = io::read_csv(dir + "/y.csv", {"x1", "x2", "x3", "y"});
  ASSERT_EQ(y.rows(), 2u);
  const double exact[2] = {study::ishigami(std::vector<double>{0.5, -1, 2}.data(), 7, 0.1),
                           study::ishigami(std::vector<double>{-2, 0.3, 0.1}.data(), 7, 0.1)};
  for (std::size_t i = 0; i < 2; ++i) EXPECT_NEAR(y.column("y")[i], exact[i], 0.1) << i;

  write_file(dir + "/far.csv", "x1,x2,x3\n0.5,-1,2\n4,0,0\n");
  EXPECT_EQ(run_command(rover_binary() + " surrogate --predict " + dir + "/ish.h5 --design " + dir +
                            "/far.csv --csv " + dir + "/far_y.csv",
                        &log),
            1);
  EXPECT_NE(log.find("far.csv:3: row 2: x1 = 4 lies outside the training support"), std::string::npos) << log;
  EXPECT_FALSE(std::ifstream(dir + "/far_y.csv").good());
}

TEST(CmdSurrogate, MonteCarloResultFileTrainsASurrogateWithItsMeansAndSds) {
  const std::string dir = rover::testing::temp_dir();
  const std::string scenario = rover::testing::short_drop_scenario(dir);
  const std::string parameters = R"("parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.3},
      "f": {"distribution": "log_uniform", "min": 1e3, "max": 1e5}}, "integrator": {"method": "rosenbrock"},
      "qoi": ["B_l_z_min", "deflection"])";
  write_file(dir + "/mc.json", R"({"type": "montecarlo", "name": "mc", "scenario": ")" + scenario + R"(", )" +
                                   parameters + R"(, "design": {"type": "sobol", "samples": 64, "seed": 5}})");
  std::string log;
  ASSERT_EQ(run_command(mpiexec() + " -np 2 " + rover_binary() + " montecarlo --study " + dir + "/mc.json --no-plot --out " +
                            dir + "/mc.h5",
                        &log),
            0)
      << log;
  write_file(dir + "/s.json", R"({"type": "surrogate", "name": "s", "scenario": ")" + scenario + R"(", )" + parameters +
                                  R"(, "training": {"file": "mc.h5"}, "pce": {"bootstrap": 50}})");
  ASSERT_EQ(run_command(surrogate("--study " + dir + "/s.json --out " + dir + "/s.h5"), &log), 0) << log;
  EXPECT_NE(log.find("from 64 runs (0 failed) of " + dir + "/mc.h5"), std::string::npos) << log;
  const io::Hdf5Reader mc(dir + "/mc.h5"), s(dir + "/s.h5");
  for (const char* qoi : {"B_l_z_min", "deflection"}) {
    const std::vector<double> mean = mc.read_doubles(std::string("/summary/") + qoi + "/mean");
    const std::vector<double> sd = mc.read_doubles(std::string("/summary/") + qoi + "/sd");
    const double pce_mean = s.read_doubles(std::string("/indices/") + qoi + "/mean").at(0);
    const double pce_sd = std::sqrt(s.read_doubles(std::string("/indices/") + qoi + "/variance").at(0));
    EXPECT_GE(pce_mean, mean[1]) << qoi;
    EXPECT_LE(pce_mean, mean[2]) << qoi;
    EXPECT_GE(pce_sd, sd[1]) << qoi;
    EXPECT_LE(pce_sd, sd[2]) << qoi;
    EXPECT_GT(s.attribute_double(std::string("/surrogate/models/") + qoi, "q2_loo"), 0.95) << qoi;
  }
  if (run_command("command -v gnuplot") == 0) {
    EXPECT_TRUE(std::ifstream(dir + "/s_surrogate.png").good()) << log;
    EXPECT_TRUE(std::ifstream(dir + "/s_surrogate_indices.png").good()) << log;
  }
}

TEST(CmdSurrogate, RefusesBadCommandLinesAndFiles) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = write_file(dir + "/s.json", R"({"type": "surrogate", "name": "s", "model": "ishigami",
      "design": {"samples": 50}})");
  std::string log;
  EXPECT_EQ(run_command(surrogate(""), &log), 1);
  EXPECT_NE(log.find("give --study S.json (train) or --predict model.h5"), std::string::npos) << log;
  EXPECT_EQ(run_command(surrogate("--study " + study + " --predict " + study), &log), 1);
  EXPECT_EQ(run_command(surrogate("--study " + study + " --samples 3 --out " + dir + "/s.h5"), &log), 1);
  EXPECT_NE(log.find("--samples 3: 3 training runs; a pce of 3 inputs needs at least 6"), std::string::npos) << log;
  EXPECT_EQ(run_command(surrogate("--predict " + study + " --design " + study + " --csv " + dir + "/y.csv"), &log), 1);
  EXPECT_NE(log.find("s.json"), std::string::npos) << log;
  write_file(dir + "/x.csv", "x1,x2,x3\n0,0,0\n");
  EXPECT_EQ(run_command(surrogate("--study " + study + " --design " + dir + "/x.csv"), &log), 1);
  EXPECT_NE(log.find("--design applies to --predict, not to --study"), std::string::npos) << log;
}

}  // namespace
}  // namespace rover
