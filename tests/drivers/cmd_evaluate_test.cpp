// `rover evaluate` through the built binary: row order, CSV and HDF5 outputs,
// equality with `rover simulate` at the same inputs, bad designs refused before
// any run with the file, line and column.
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "io/hdf5_file.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using rover::testing::mpiexec;
using rover::testing::rover_binary;
using rover::testing::run_command;
using rover::testing::source_path;

using rover::testing::write_file;

// The evaluate CSV: '#' comments, a header, then numbers and a quoted message
// last. Returns the numeric columns by name.
std::map<std::string, std::vector<double>> read_output(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> header;
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    if (header.empty()) {
      header = cells;
      continue;
    }
    for (std::size_t j = 0; j + 1 < header.size(); ++j) columns[header[j]].push_back(std::stod(cells.at(j)));
  }
  return columns;
}

std::string short_drop(const std::string& dir) { return rover::testing::short_drop_scenario(dir); }

TEST(CmdEvaluate, RowsComeBackInOrderAndMatchSimulate) {
  const std::string dir = rover::testing::temp_dir();
  const std::string scenario = short_drop(dir);
  // A byte-order mark, a comment and a blank line are accepted.
  write_file(dir + "/x.csv", "\xEF\xBB\xBF" "c_q,scenario.initial_q.z\n# two drop heights\n0.30,0.285\n\n0.10,0.281\n0.20,0.283\n");
  std::string log;
  ASSERT_EQ(run_command(mpiexec() + " -np 2 " + rover_binary() + " evaluate --scenario " + scenario + " --design " +
                            dir + "/x.csv --qoi B_l_z_min,at_rest --channels B_l_z --out " + dir + "/y.h5", &log), 0)
      << log;
  ASSERT_EQ(run_command(rover_binary() + " evaluate --scenario " + scenario + " --design " + dir +
                            "/x.csv --qoi B_l_z_min,at_rest --out " + dir + "/y.csv", &log), 0) << log;
  const io::Hdf5Reader h5(dir + "/y.h5");
  auto csv = read_output(dir + "/y.csv");
  EXPECT_EQ(csv["c_q"], (std::vector<double>{0.30, 0.10, 0.20}));
  // Plain CSV: the header is the first line (csv.DictReader, pandas.read_csv).
  std::ifstream plain(dir + "/y.csv");
  std::string first_line;
  std::getline(plain, first_line);
  EXPECT_EQ(first_line.rfind("c_q,", 0), 0u) << first_line;
  EXPECT_EQ(h5.read_matrix("/inputs/values").col(0), Eigen::Vector3d(0.30, 0.10, 0.20));
  EXPECT_EQ(csv["B_l_z_min"], h5.read_doubles("/qoi/B_l_z_min"));  // CSV round trip is exact
  EXPECT_EQ(csv["status"], (std::vector<double>{0, 0, 0}));

  // Row 2 (c_q = 0.10, z = 0.281) is exactly `rover simulate --cq 0.10` on the scenario.
  ASSERT_EQ(run_command(rover_binary() + " simulate --scenario " + scenario + " --cq 0.10 --no-plot --out " + dir +
                            "/sim.h5", &log), 0) << log;
  const io::Hdf5Reader sim(dir + "/sim.h5");
  const std::vector<double> z = sim.read_doubles("/B_l_z");
  const Eigen::MatrixXd curves = h5.read_matrix("/curves/B_l_z");
  ASSERT_EQ(curves.cols(), static_cast<Eigen::Index>(z.size()));
  for (std::size_t k = 0; k < z.size(); ++k) EXPECT_EQ(curves(1, static_cast<Eigen::Index>(k)), z[k]) << k;
  EXPECT_EQ(h5.read_doubles("/qoi/B_l_z_min")[1], *std::min_element(z.begin(), z.end()));
  EXPECT_EQ(h5.read_doubles("/qoi/at_rest")[1], z.back());
  // A higher drop ends at the same rest height but falls further first.
  EXPECT_NEAR(csv["at_rest"][0], csv["at_rest"][1], 2e-3);
}

// A row that cannot finish within its wall-time budget (5 ms for a drop
// that takes Dormand-Prince a tenth of a second) is stopped and recorded as
// failed with the reason; the other rows run.
TEST(CmdEvaluate, ARowThatCannotFinishIsAFailedRowWithItsReason) {
  const std::string dir = rover::testing::temp_dir();
  write_file(dir + "/x.csv", "scenario.wall_time_budget\n0.005\n10\n");
  const std::string scenario = write_file(dir + "/budget.json", R"({"name": "short_drop", "rover": ")" +
                                                                    source_path("configs/rover.json") +
                                                                    R"(", "duration": 0.25, "output_rate": 200,
      "initial_q": {"z": 0.281, "chi": 0.039, "psi": 0.0042}})");
  std::string log;
  EXPECT_EQ(run_command(rover_binary() + " evaluate --scenario " + scenario + " --integrator dopri5 --design " +
                            dir + "/x.csv --qoi B_l_z_min --out " + dir + "/y.csv", &log), 2) << log;
  auto csv = read_output(dir + "/y.csv");
  EXPECT_EQ(csv["status"], (std::vector<double>{3, 0}));  // time budget exceeded; ok
  EXPECT_TRUE(std::isnan(csv["B_l_z_min"][0]));
  EXPECT_GT(csv["B_l_z_min"][1], 0.1);
  std::ifstream in(dir + "/y.csv");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("time budget exceeded at t = "), std::string::npos) << text;
  EXPECT_NE(text.find("wall-time budget used up"), std::string::npos) << text;
}

TEST(CmdEvaluate, BadDesignsNameFileLineAndColumnBeforeAnyRun) {
  const std::string dir = rover::testing::temp_dir();
  const std::string scenario = short_drop(dir);
  struct Case { std::string csv, expected; };
  const std::vector<Case> cases{
      {"c_q,f\n0.1,1e4\n0.2,abc\n", ":3: column 2 (f): 'abc'"},
      {"c_q,f\n0.1,1e4\n0.2\n", ":3: expected 2 values"},
      {"c_q,bodies.chassis.mas\n0.1,1\n", "did you mean 'bodies.chassis.mass'"},
      {"c_q,s_structure.c_q\n0.1,0.1\n", "the same parameter"},
      {"c_q,bodies.chassis.mass\n0.1,1.2\n0.1,-1\n", ":3: this row's values"},
      {"M0_11\n-0.5\n", "preload"},
      {"c_q\n", "no rows"},
      {"c_q,f\n0.1,inf\n", "not a finite number"},
  };
  for (const Case& c : cases) {
    write_file(dir + "/bad.csv", c.csv);
    std::string log;
    EXPECT_NE(run_command(rover_binary() + " evaluate --scenario " + scenario + " --design " + dir +
                              "/bad.csv --out " + dir + "/bad_out.csv", &log), 0) << c.csv;
    EXPECT_NE(log.find("bad.csv"), std::string::npos) << log;
    EXPECT_NE(log.find(c.expected), std::string::npos) << c.csv << "\n" << log;
    EXPECT_EQ(log.find("evaluate: 0/"), std::string::npos) << "no run may start: " << log;
    EXPECT_FALSE(std::ifstream(dir + "/bad_out.csv").good());
  }
}

}  // namespace
}  // namespace rover
