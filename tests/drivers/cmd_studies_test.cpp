// End-to-end tests of the study subcommands (montecarlo, surface, calibrate)
// through the built `rover`, with and without mpirun.
#include <cstdlib>
#include <fstream>

#include <gtest/gtest.h>

#include "io/hdf5_file.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using rover::testing::mpiexec;
using rover::testing::rover_binary;
using rover::testing::run_command;
using rover::testing::source_path;

void write_file(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

// A short drop (0.25 s at 200 Hz) so that studies run in seconds.
std::string short_drop(const std::string& dir) {
  const std::string path = dir + "/short_drop.json";
  write_file(path, R"({"name": "short_drop", "rover": ")" + source_path("configs/rover.json") +
                       R"(", "duration": 0.25, "output_rate": 200,
      "initial_q": {"z": 0.281, "chi": 0.039, "psi": 0.0042}})");
  return path;
}

std::string mc_study(const std::string& dir, double sd_scale, int samples = 6) {
  const std::string path = dir + "/mc_" + std::to_string(sd_scale) + ".json";
  write_file(path, R"({"type": "montecarlo", "name": "mc", "scenario": ")" + short_drop(dir) +
                       R"(", "samples": )" + std::to_string(samples) +
                       R"(, "seed": 99, "sd_scale": )" + std::to_string(sd_scale) + "}");
  return path;
}

TEST(CmdStudies, MonteCarloIsIdenticalOnOneAndTwoRanks) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = mc_study(dir, 1.0);
  std::string log;
  ASSERT_EQ(run_command(mpiexec() + " -np 1 " + rover_binary() + " montecarlo --study " + study +
                            " --no-plot --out " + dir + "/np1.h5", &log), 0) << log;
  ASSERT_EQ(run_command(mpiexec() + " -np 2 " + rover_binary() + " montecarlo --study " + study +
                            " --no-plot --out " + dir + "/np2.h5", &log), 0) << log;
  const io::Hdf5Reader a(dir + "/np1.h5"), b(dir + "/np2.h5");
  for (const char* name : {"/samples/M0", "/curves/B_l_z", "/band/mean", "/band/std", "/band/lower",
                           "/band/upper", "/band/p00135", "/band/p99865", "/samples/deflection",
                           "/samples/at_rest", "/t"})
    EXPECT_EQ(a.read_doubles(name), b.read_doubles(name)) << name;
  EXPECT_EQ(a.shape("/curves/B_l_z"), (std::vector<std::size_t>{6, 51}));
  const auto mean = a.read_doubles("/band/mean"), lower = a.read_doubles("/band/lower"),
             upper = a.read_doubles("/band/upper");
  for (std::size_t t = 0; t < mean.size(); ++t) {
    EXPECT_LE(lower[t], mean[t]);
    EXPECT_LE(mean[t], upper[t]);
  }
  EXPECT_GT(a.read_doubles("/band/std").back(), 0.0);  // preloads really vary the response
}

TEST(CmdStudies, BandCollapsesWhenEveryStandardDeviationIsZero) {
  const std::string dir = rover::testing::temp_dir();
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " montecarlo --study " + mc_study(dir, 0.0, 3) +
                            " --no-plot --out " + dir + "/mc0.h5", &log), 0) << log;
  const io::Hdf5Reader h5(dir + "/mc0.h5");
  const auto mean = h5.read_doubles("/band/mean"), lower = h5.read_doubles("/band/lower"),
             upper = h5.read_doubles("/band/upper"), sd = h5.read_doubles("/band/std");
  for (std::size_t t = 0; t < mean.size(); ++t) {
    EXPECT_EQ(sd[t], 0.0);
    EXPECT_EQ(lower[t], mean[t]);
    EXPECT_EQ(upper[t], mean[t]);
  }
}

TEST(CmdStudies, SurfaceOnTwoRanksHasTheGridShapes) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = dir + "/surface.json";
  write_file(study, R"({"type": "surface", "name": "s", "scenario": ")" + short_drop(dir) + R"(",
      "reference": {"simulate": {"f": 1e4, "c_q": 0.14}},
      "f": {"min": 1e3, "max": 1e4, "count": 2, "spacing": "log"},
      "c_q": {"min": 0.1, "max": 0.14, "count": 2},
      "sweep": {"f": {"min": 1e2, "max": 1e4, "count": 3, "spacing": "log"}, "c_q": 0.14}})");
  std::string log;
  ASSERT_EQ(run_command(mpiexec() + " -np 2 " + rover_binary() + " surface --study " + study +
                            " --no-plot --out " + dir + "/s.h5", &log), 0) << log;
  const io::Hdf5Reader h5(dir + "/s.h5");
  EXPECT_EQ(h5.shape("/rms"), (std::vector<std::size_t>{2, 2}));
  const auto rms = h5.read_doubles("/rms");
  EXPECT_EQ(rms[3], 0.0);  // (f, c_q) = reference: identical curve
  EXPECT_GT(rms[0], 0.0);
  for (double t : h5.read_doubles("/t_c")) EXPECT_GT(t, 0.0);
  EXPECT_EQ(h5.read_doubles("/sweep/regression").size(), 3u);
  EXPECT_EQ(h5.attribute_string("/", "integrator"), "dopri5");
}

TEST(CmdStudies, CalibrationRecoversTheGeneratingDamping) {
  // configs/data/drop_horizontal_synthetic.csv was made at c_q = 0.25 with
  // 0.1 mm noise and a 0.05 s offset (see its header).
  const std::string dir = rover::testing::temp_dir();
  std::string log;
  ASSERT_EQ(run_command("cd " + source_path("") + " && " + rover_binary() +
                            " calibrate --fit c_q --algorithm LN_BOBYQA --no-plot --out " + dir +
                            "/cal.h5", &log), 0) << log;
  const io::Hdf5Reader h5(dir + "/cal.h5");
  const double c_q = h5.read_doubles("/best/values").at(0);
  EXPECT_NEAR(c_q, 0.25, 0.05 * 0.25) << log;
  EXPECT_NEAR(h5.read_doubles("/best/time_offset").at(0), 0.05, 2e-3);
  EXPECT_GT(h5.shape("/history").at(0), 3u);
}

TEST(CmdStudies, BadStudyConfigsNameTheField) {
  const std::string dir = rover::testing::temp_dir();
  const std::string scenario = short_drop(dir);
  struct Case { std::string command, json, expected; };
  const std::vector<Case> cases{
      {"montecarlo", R"({"type": "montecarlo", "name": "m", "scenario": ")" + scenario + R"(", "samples": 0, "seed": 1})", "samples"},
      {"montecarlo", R"({"type": "montecarlo", "name": "m", "scenario": ")" + scenario + R"(", "samples": 3, "seed": 1, "sampels": 2})", "sampels"},
      {"surface", R"({"type": "surface", "name": "s", "scenario": ")" + scenario + R"(", "reference": {"simulate": {}},
          "f": {"min": 1e3, "max": 1e4, "count": 0}, "c_q": {"min": 0.1, "max": 0.2, "count": 2}})", "f.count"},
      {"surface", R"({"type": "surface", "name": "s", "scenario": ")" + scenario + R"(", "reference": {"simulate": {}},
          "f": {"min": 1e4, "max": 1e3, "count": 2}, "c_q": {"min": 0.1, "max": 0.2, "count": 2}})", "f.max"},
      {"calibrate", R"({"type": "calibration", "name": "c", "scenario": ")" + scenario + R"(", "data": ")" +
          source_path("configs/data/drop_horizontal_synthetic.csv") + R"(", "fit": ["c_q"],
          "bounds": {"c_q": [1.0, 0.1]}, "initial": {"c_q": 0.5}})", "bounds.c_q"},
  };
  for (const Case& c : cases) {
    const std::string path = dir + "/bad.json";
    write_file(path, c.json);
    std::string log;
    EXPECT_NE(run_command(rover_binary() + " " + c.command + " --study " + path + " --no-plot --out " +
                              dir + "/bad.h5", &log), 0);
    EXPECT_NE(log.find(path), std::string::npos) << log;
    EXPECT_NE(log.find("'" + c.expected + "'"), std::string::npos) << log;
  }
}

}  // namespace
}  // namespace rover
