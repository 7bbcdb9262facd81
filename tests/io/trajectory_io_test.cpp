// Trajectory files (io/trajectory_io.cpp; docs/model.md §8): the HDF5 file
// round-trips through Hdf5Reader and opens in h5py with the documented
// datasets, shapes and attributes; the CSV round-trips exactly; read_curve
// reads both, and measured t,z data.
#include "io/trajectory_io.hpp"

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/csv.hpp"
#include "io/hdf5_file.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using testing::source_path;

// A hand-made trajectory with distinct, non-round values in every cell.
Trajectory sample_trajectory(int samples = 7) {
  Trajectory tr;
  tr.status = SimulationStatus::kOk;
  tr.q.resize(samples, kNumCoordinates);
  tr.u.resize(samples, kNumCoordinates);
  tr.normal_force_N.resize(samples, kNumLegs);
  for (int i = 0; i < samples; ++i) {
    const double t = 1e-3 * i;
    tr.t.push_back(t);
    tr.B_l_z.push_back(0.1 + 0.01 * std::sin(7.0 * i + 0.1));
    tr.B_r_z.push_back(0.1 + 0.01 * std::sin(5.0 * i + 0.2));
    tr.G_z.push_back(0.2 + 0.01 * std::cos(3.0 * i));
    tr.pitch.push_back(0.039 / (1.0 + i));
    tr.roll.push_back(-0.0042 * std::sqrt(1.0 + i));
    for (int c = 0; c < kNumCoordinates; ++c) {
      tr.q(i, c) = std::sin(0.37 * c + 1.3 * i) / 3.0;
      tr.u(i, c) = std::cos(0.11 * c - 0.7 * i) * 1.7;
    }
    for (int leg = 0; leg < kNumLegs; ++leg) tr.normal_force_N(i, leg) = 10.0 + leg + 0.1 * i / 3.0;
  }
  tr.wall_time_s = 1.25;
  tr.rhs_evaluations = 123457;
  tr.steps = 20576;
  tr.min_step_s = 1.5e-6;
  tr.max_step_s = 3.25e-4;
  return tr;
}

io::ScenarioSetup sample_setup() {
  io::ScenarioSetup setup = io::load_scenario(source_path("configs/scenarios/drop_horizontal.json"));
  setup.scenario.integrator.relative_tolerance = 2e-7;  // not the default, so it is really recorded
  setup.scenario.integrator.absolute_tolerance = 3e-10;
  return setup;
}

ModelInputs sample_inputs() {
  ModelInputs in;
  in.sharpness_f = 2.5e3;
  in.damping_c_q = 0.21;
  in.preload_Nm = {1.9, 1.3, 2.1, 1.2, 1.7, 1.5, 2.0, 1.1};
  return in;
}

TEST(TrajectoryIo, Hdf5RoundTrip) {
  const Trajectory tr = sample_trajectory();
  const io::ScenarioSetup setup = sample_setup();
  const ModelInputs in = sample_inputs();
  const std::string path = testing::temp_dir() + "/run.h5";
  io::write_trajectory_hdf5(path, tr, setup, in);

  const io::Hdf5Reader h5(path);
  const std::size_t T = tr.t.size();
  const std::pair<const char*, const std::vector<double>*> series[] = {
      {"/t", &tr.t}, {"/B_l_z", &tr.B_l_z}, {"/B_r_z", &tr.B_r_z},
      {"/G_z", &tr.G_z}, {"/pitch", &tr.pitch}, {"/roll", &tr.roll}};
  for (const auto& [name, values] : series) {
    EXPECT_EQ(h5.shape(name), std::vector<std::size_t>{T}) << name;
    EXPECT_EQ(h5.read_doubles(name), *values) << name;
  }
  EXPECT_EQ(h5.shape("/q"), (std::vector<std::size_t>{T, 23}));
  EXPECT_EQ(h5.shape("/u"), (std::vector<std::size_t>{T, 23}));
  EXPECT_EQ(h5.shape("/Fn"), (std::vector<std::size_t>{T, 4}));
  EXPECT_EQ(h5.read_matrix("/q"), Eigen::MatrixXd(tr.q));
  EXPECT_EQ(h5.read_matrix("/u"), Eigen::MatrixXd(tr.u));
  EXPECT_EQ(h5.read_matrix("/Fn"), Eigen::MatrixXd(tr.normal_force_N));
  const std::vector<std::string> names = h5.read_strings("/coordinate_names");
  ASSERT_EQ(names.size(), 23u);
  EXPECT_EQ(names.front(), "x");
  EXPECT_EQ(names[4], "chi");
  EXPECT_EQ(names.back(), "z4");

  EXPECT_EQ(h5.attribute_double("/", "f"), in.sharpness_f);
  EXPECT_EQ(h5.attribute_double("/", "c_q"), in.damping_c_q);
  EXPECT_EQ(h5.attribute_doubles("/", "M0"), std::vector<double>(in.preload_Nm.begin(), in.preload_Nm.end()));
  EXPECT_EQ(h5.attribute_string("/", "integrator"), "dopri5");
  EXPECT_EQ(h5.attribute_double("/", "rtol"), 2e-7);
  EXPECT_EQ(h5.attribute_double("/", "atol"), 3e-10);
  EXPECT_EQ(h5.attribute_double("/", "wall_time_s"), tr.wall_time_s);
  EXPECT_EQ(h5.attribute_integer("/", "rhs_evaluations"), tr.rhs_evaluations);
  EXPECT_EQ(h5.attribute_integer("/", "steps"), tr.steps);
  EXPECT_EQ(h5.attribute_double("/", "smallest_step_s"), tr.min_step_s);
  EXPECT_EQ(h5.attribute_double("/", "largest_step_s"), tr.max_step_s);
  EXPECT_EQ(h5.attribute_string("/", "project_version"), ROVER_VERSION);
  EXPECT_EQ(h5.attribute_string("/", "status"), "ok");
  EXPECT_EQ(h5.attribute_string("/", "scenario"), "drop_horizontal");
  EXPECT_EQ(h5.attribute_double("/", "duration_s"), 1.0);
  const auto& g = setup.model.parameters.friction.gammas;
  EXPECT_EQ(h5.attribute_doubles("/", "friction_gammas"), std::vector<double>(g.begin(), g.end()));
  // The configs themselves are recorded, so the run can be reproduced from the file.
  EXPECT_EQ(nlohmann::json::parse(h5.attribute_string("/", "rover_json")),
            io::read_json_file(source_path("configs/rover.json")));
  EXPECT_NE(h5.attribute_string("/", "scenario_json").find("drop_horizontal"), std::string::npos);
}

TEST(TrajectoryIo, FailedRunRecordsWhy) {
  Trajectory tr = sample_trajectory(3);
  tr.status = SimulationStatus::kStepSizeUnderflow;
  tr.message = "step size underflow at t = 0.002 s: step below min_step";
  const std::string path = testing::temp_dir() + "/failed.h5";
  io::write_trajectory_hdf5(path, tr, sample_setup(), sample_inputs());
  const io::Hdf5Reader h5(path);
  EXPECT_EQ(h5.attribute_string("/", "status"), "step size underflow");
  EXPECT_EQ(h5.attribute_integer("/", "status_code"), 2);
  EXPECT_EQ(h5.attribute_string("/", "message"), tr.message);
  // Its samples are finite, but it is no trajectory: read_curve refuses it
  // with the recorded status and message.
  try {
    io::read_curve(path);
    ADD_FAILURE() << "read the record of a failed run as a curve";
  } catch (const io::ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path + ": the record of a failed run (status 'step size underflow'"), std::string::npos) << m;
    EXPECT_NE(m.find(tr.message), std::string::npos) << m;
  }
}

TEST(TrajectoryIo, OpensInH5py) {
  std::string out;
  if (testing::run_command("/usr/bin/python3 -c 'import h5py'", &out) != 0)
    GTEST_SKIP() << "/usr/bin/python3 has no h5py (scripts/setup.sh installs python3-h5py): " << out;
  const Trajectory tr = sample_trajectory(5);
  const std::string path = testing::temp_dir() + "/run.h5";
  io::write_trajectory_hdf5(path, tr, sample_setup(), sample_inputs());
  const std::string script =
      "import h5py, json, sys\n"
      "f = h5py.File(sys.argv[1], 'r')\n"
      "a = f.attrs\n"
      "def text(v): return v.decode() if isinstance(v, bytes) else str(v)\n"
      "print(json.dumps({'shapes': {k: list(f[k].shape) for k in f.keys()},\n"
      "  'q21': float(f['q'][2, 1]), 'Fn31': float(f['Fn'][3, 1]), 't': [float(x) for x in f['t'][:]],\n"
      "  'f': float(a['f']), 'c_q': float(a['c_q']), 'M0': [float(x) for x in a['M0']],\n"
      "  'integrator': text(a['integrator']), 'rtol': float(a['rtol']), 'atol': float(a['atol']),\n"
      "  'wall_time_s': float(a['wall_time_s']), 'rhs_evaluations': int(a['rhs_evaluations']),\n"
      "  'project_version': text(a['project_version']),\n"
      "  'names': [text(x) for x in f['coordinate_names'][:]]}))\n";
  const std::string script_path = testing::temp_dir() + "/read.py";
  std::ofstream(script_path) << script;
  ASSERT_EQ(testing::run_command("/usr/bin/python3 " + script_path + " " + path, &out), 0) << out;
  const nlohmann::json j = nlohmann::json::parse(out);
  const nlohmann::json& shapes = j["shapes"];
  for (const char* name : {"t", "B_l_z", "B_r_z", "G_z", "pitch", "roll"})
    EXPECT_EQ(shapes[name], nlohmann::json({5})) << name;
  EXPECT_EQ(shapes["q"], nlohmann::json({5, 23}));
  EXPECT_EQ(shapes["u"], nlohmann::json({5, 23}));
  EXPECT_EQ(shapes["Fn"], nlohmann::json({5, 4}));
  EXPECT_EQ(j["q21"].get<double>(), tr.q(2, 1));  // row-major: sample 2, coordinate y
  EXPECT_EQ(j["Fn31"].get<double>(), tr.normal_force_N(3, 1));
  EXPECT_EQ(j["t"].get<std::vector<double>>(), tr.t);
  const ModelInputs in = sample_inputs();
  EXPECT_EQ(j["f"].get<double>(), in.sharpness_f);
  EXPECT_EQ(j["c_q"].get<double>(), in.damping_c_q);
  EXPECT_EQ(j["M0"].get<std::vector<double>>(), std::vector<double>(in.preload_Nm.begin(), in.preload_Nm.end()));
  EXPECT_EQ(j["integrator"], "dopri5");
  EXPECT_EQ(j["rtol"].get<double>(), 2e-7);
  EXPECT_EQ(j["atol"].get<double>(), 3e-10);
  EXPECT_EQ(j["wall_time_s"].get<double>(), tr.wall_time_s);
  EXPECT_EQ(j["rhs_evaluations"].get<long>(), tr.rhs_evaluations);
  EXPECT_EQ(j["project_version"], ROVER_VERSION);
  EXPECT_EQ(j["names"].size(), 23u);
}

TEST(TrajectoryIo, CsvRoundTrip) {
  const Trajectory tr = sample_trajectory();
  const std::string path = testing::temp_dir() + "/run.csv";
  io::write_trajectory_csv(path, tr);
  const io::CsvTable table = io::read_csv(path);
  ASSERT_EQ(table.header.size(), 6u + 23u + 23u + 4u);
  ASSERT_EQ(table.rows(), tr.t.size());
  EXPECT_EQ(table.column("t"), tr.t);
  EXPECT_EQ(table.column("B_l_z"), tr.B_l_z);
  EXPECT_EQ(table.column("B_r_z"), tr.B_r_z);
  EXPECT_EQ(table.column("G_z"), tr.G_z);
  EXPECT_EQ(table.column("pitch"), tr.pitch);
  EXPECT_EQ(table.column("roll"), tr.roll);
  for (int c = 0; c < kNumCoordinates; ++c) {
    const std::vector<double>& qc = table.column(std::string("q_") + kCoordinateNames[c]);
    const std::vector<double>& uc = table.column(std::string("u_") + kCoordinateNames[c]);
    for (std::size_t i = 0; i < tr.t.size(); ++i) {
      EXPECT_EQ(qc[i], tr.q(static_cast<Eigen::Index>(i), c)) << kCoordinateNames[c];
      EXPECT_EQ(uc[i], tr.u(static_cast<Eigen::Index>(i), c)) << kCoordinateNames[c];
    }
  }
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const std::vector<double>& fn = table.column("Fn_" + std::to_string(leg + 1));
    for (std::size_t i = 0; i < tr.t.size(); ++i) EXPECT_EQ(fn[i], tr.normal_force_N(static_cast<Eigen::Index>(i), leg));
  }
}

// A stop request (a signal's flag) set when a file is to be written:
// false, no temporary left, and an earlier file at the path as it was; with
// the flag down the files are written.
TEST(TrajectoryIo, AStoppedWriterLeavesTheEarlierFile) {
  const Trajectory tr = sample_trajectory(5000);  // more rows than one check of the CSV writer
  const std::string dir = testing::temp_dir();
  std::atomic<bool> stop{true};
  for (const std::string& path : {dir + "/run.h5", dir + "/run.csv"}) {
    SCOPED_TRACE(path);
    std::ofstream(path) << "an earlier result";
    const bool written = path.ends_with(".h5")
                             ? io::write_trajectory_hdf5(path, tr, sample_setup(), sample_inputs(), &stop)
                             : io::write_trajectory_csv(path, tr, &stop);
    EXPECT_FALSE(written);
    std::ifstream in(path);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()), "an earlier result");
    EXPECT_FALSE(std::filesystem::exists(path + ".partial"));
  }
  stop = false;
  EXPECT_TRUE(io::write_trajectory_hdf5(dir + "/run.h5", tr, sample_setup(), sample_inputs(), &stop));
  EXPECT_TRUE(io::write_trajectory_csv(dir + "/run.csv", tr, &stop));
  EXPECT_EQ(io::read_curve(dir + "/run.h5").y, tr.B_l_z);
  EXPECT_EQ(io::read_curve(dir + "/run.csv").y, tr.B_l_z);
}

TEST(TrajectoryIo, ReadCurveFromHdf5CsvAndMeasuredData) {
  const Trajectory tr = sample_trajectory();
  const std::string dir = testing::temp_dir();
  io::write_trajectory_hdf5(dir + "/run.h5", tr, sample_setup(), sample_inputs());
  io::write_trajectory_csv(dir + "/run.csv", tr);
  for (const std::string& file : {dir + "/run.h5", dir + "/run.csv"}) {
    SCOPED_TRACE(file);
    const io::Curve bl = io::read_curve(file);  // B_l_z by default
    EXPECT_EQ(bl.t, tr.t);
    EXPECT_EQ(bl.y, tr.B_l_z);
    const io::Curve g = io::read_curve(file, "G_z");
    EXPECT_EQ(g.y, tr.G_z);
  }
  // Measured drop data: a 't,z' table with comments.
  std::ofstream(dir + "/measured.csv") << "# B_l z from the drop rig [s, m]\nt,z\n0.0,0.281\n0.01,0.2795\n0.02,0.2751\n";
  const io::Curve m = io::read_curve(dir + "/measured.csv");
  EXPECT_EQ(m.t, (std::vector<double>{0.0, 0.01, 0.02}));
  EXPECT_EQ(m.y, (std::vector<double>{0.281, 0.2795, 0.2751}));
  // A missing column is an error that names it.
  try {
    io::read_curve(dir + "/run.h5", "B_x_z");
    ADD_FAILURE() << "read a missing dataset";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("B_x_z"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rover
