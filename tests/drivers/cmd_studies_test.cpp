// End-to-end tests of the study subcommands (montecarlo, surface; calibrate
// has tests/drivers/cmd_calibrate_test.cpp)
// through the built `rover`, with and without mpirun.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "core/integrators.hpp"
#include "io/hdf5_file.hpp"
#include "test_support.hpp"

namespace rover {
namespace {

using rover::testing::mpiexec;
using rover::testing::rover_binary;
using rover::testing::run_command;
using rover::testing::signal_once_checkpoint_grows;
using rover::testing::source_path;

using rover::testing::write_file;

// A short drop (0.25 s at 200 Hz) so that studies run in seconds.
std::string short_drop(const std::string& dir) { return rover::testing::short_drop_scenario(dir); }

// A Monte Carlo over the preloads (sd_scale times their sds) and, with
// `four_inputs`, c_q, f and the drop height too, on a design of `design` type.
std::string mc_study(const std::string& dir, double sd_scale, int samples = 6, bool four_inputs = false,
                     const std::string& design = "monte_carlo") {
  const std::string path = dir + "/mc_" + std::to_string(sd_scale) + design + ".json";
  const std::string parameters =
      four_inputs ? R"("c_q": {"distribution": "uniform", "min": 0.1, "max": 0.3},
                       "f": {"distribution": "log_uniform", "min": 1e3, "max": 1e5},
                       "contact.k_g": {"distribution": "normal", "sd_percent": 5},
                       "scenario.initial_q.z": {"distribution": "uniform", "min": 0.275, "max": 0.29})"
                  : R"("M0": {"distribution": "normal", "from_config": true, "sd_scale": )" +
                        std::to_string(sd_scale) + "}";
  write_file(path, R"({"type": "montecarlo", "name": "mc", "scenario": ")" + short_drop(dir) +
                       R"(", "integrator": {"method": "rosenbrock"}, "parameters": {)" + parameters +
                       R"(}, "design": {"type": ")" + design + R"(", "samples": )" + std::to_string(samples) +
                       R"(, "seed": 99}, "qoi": ["B_l_z_min", "t_min", "deflection", "at_rest"],
                       "channels": ["B_l_z", "G_z"]})");
  return path;
}

const std::vector<std::string> kMonteCarloDatasets{
    "/inputs/values", "/curves/B_l_z", "/curves/G_z", "/bands/B_l_z/mean", "/bands/B_l_z/std",
    "/bands/B_l_z/lower", "/bands/B_l_z/upper", "/bands/B_l_z/p00135", "/bands/B_l_z/p99865",
    "/bands/G_z/mean", "/qoi/B_l_z_min", "/qoi/t_min", "/qoi/deflection", "/qoi/at_rest",
    "/summary/deflection/mean", "/summary/deflection/sd", "/t"};

TEST(CmdStudies, MonteCarloOfFourInputsIsIdenticalOnOneTwoThreeAndEightRanks) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = mc_study(dir, 1.0, 7, true, "sobol");
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " montecarlo --study " + study + " --no-plot --out " + dir + "/np1.h5", &log), 0)
      << log;
  // Eight ranks: more ranks than cores, and one with no task at all (7 runs).
  for (const char* np : {"2", "3", "8"}) {
    ASSERT_EQ(run_command(mpiexec() + " -np " + np + " " + rover_binary() + " montecarlo --study " + study +
                              " --no-plot --out " + dir + "/np" + np + ".h5", &log), 0) << log;
    const io::Hdf5Reader a(dir + "/np1.h5"), b(dir + "/np" + np + ".h5");
    for (const std::string& name : kMonteCarloDatasets) EXPECT_EQ(a.read_doubles(name), b.read_doubles(name)) << name;
  }
  const io::Hdf5Reader a(dir + "/np1.h5");
  EXPECT_EQ(a.shape("/curves/B_l_z"), (std::vector<std::size_t>{7, 51}));
  EXPECT_EQ(a.shape("/inputs/values"), (std::vector<std::size_t>{7, 4}));
  EXPECT_EQ(a.read_strings("/inputs/names"),
            (std::vector<std::string>{"s_structure.c_q", "s_structure.f", "contact.k_g", "scenario.initial_q.z"}));
  // Each run's drop height is its input: a higher drop starts higher.
  const Eigen::MatrixXd x = a.read_matrix("/inputs/values");
  const Eigen::MatrixXd g = a.read_matrix("/curves/G_z");
  for (Eigen::Index i = 0; i < x.rows(); ++i) EXPECT_NEAR(g(i, 0), x(i, 3), 1e-12);
  const auto mean = a.read_doubles("/bands/B_l_z/mean"), lower = a.read_doubles("/bands/B_l_z/lower"),
             upper = a.read_doubles("/bands/B_l_z/upper");
  for (std::size_t t = 0; t < mean.size(); ++t) {
    EXPECT_LE(lower[t], mean[t]);
    EXPECT_LE(mean[t], upper[t]);
  }
  // The QoIs are those of the stored curves.
  const Eigen::MatrixXd z = a.read_matrix("/curves/B_l_z");
  const auto z_min = a.read_doubles("/qoi/B_l_z_min"), rest = a.read_doubles("/qoi/at_rest");
  for (Eigen::Index i = 0; i < z.rows(); ++i) {
    EXPECT_EQ(z_min[static_cast<std::size_t>(i)], z.row(i).minCoeff());
    EXPECT_EQ(rest[static_cast<std::size_t>(i)], z(i, z.cols() - 1));
  }
}

TEST(CmdStudies, MonteCarloResumedAfterAKillRecomputesOnlyWhatIsMissing) {
  const std::string dir = rover::testing::temp_dir();
  constexpr int kRuns = 100;
  const std::string study = mc_study(dir, 1.0, kRuns);
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " montecarlo --study " + study + " --no-plot --out " + dir + "/whole.h5", &log), 0)
      << log;
  // Killed (SIGKILL) once part of the runs is checkpointed: the checkpoint is
  // written every record here (--checkpoint-every 1).
  run_command("cd " + dir + " && " +
                  signal_once_checkpoint_grows(rover_binary() + " montecarlo --study " + study +
                                                   " --checkpoint-every 1 --no-plot --out " + dir + "/part.h5",
                                               dir + "/part.h5.checkpoint", "KILL"),
              &log);
  ASSERT_FALSE(std::ifstream(dir + "/part.h5").good()) << "the killed run must not leave a result file";
  ASSERT_TRUE(std::ifstream(dir + "/part.h5.checkpoint").good()) << log;
  ASSERT_EQ(run_command(rover_binary() + " montecarlo --study " + study + " --no-plot --resume --out " + dir +
                            "/part.h5", &log), 0) << log;
  const std::size_t pos = log.find("resuming, ");
  ASSERT_NE(pos, std::string::npos) << log;
  const int reused = std::stoi(log.substr(pos + 10));
  EXPECT_GT(reused, 0) << log;
  EXPECT_LT(reused, kRuns) << log;
  const io::Hdf5Reader a(dir + "/whole.h5"), b(dir + "/part.h5");
  for (const std::string& name : kMonteCarloDatasets) {
    if (name.find("G_z") == std::string::npos) {
      EXPECT_EQ(a.read_doubles(name), b.read_doubles(name)) << name;
    }
  }
}

TEST(CmdStudies, MonteCarloResumeRefusesChangedOptions) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = mc_study(dir, 1.0, 50);
  std::string log;
  // Leave a checkpoint behind: kill once it holds a run.
  run_command("cd " + dir + " && " +
                  signal_once_checkpoint_grows(rover_binary() + " montecarlo --study " + study +
                                                   " --checkpoint-every 1 --no-plot --out " + dir + "/r.h5",
                                               dir + "/r.h5.checkpoint", "KILL"),
              &log);
  ASSERT_TRUE(std::ifstream(dir + "/r.h5.checkpoint").good()) << log;
  ASSERT_FALSE(std::ifstream(dir + "/r.h5").good()) << "the study finished before the kill: " << log;
  EXPECT_NE(run_command(rover_binary() + " montecarlo --study " + study + " --seed 5 --no-plot --resume --out " +
                            dir + "/r.h5", &log), 0);
  // The flag that differs is named, with the value the checkpoint's runs were made with.
  EXPECT_NE(log.find("--seed 5 here"), std::string::npos) << log;
  EXPECT_NE(log.find("seed 99 (from the study file, no --seed)"), std::string::npos) << log;
}

TEST(CmdStudies, InterruptSavesTheCheckpointAndTellsHowToResume) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = mc_study(dir, 1.0, 400);
  for (const char* sig : {"INT", "TERM"}) {
    std::string log;
    const std::string out = dir + "/int_" + sig + ".h5";
    const int status = run_command(
        "cd " + dir + " && " +
            signal_once_checkpoint_grows(rover_binary() + " montecarlo --study " + study +
                                             " --checkpoint-every 1 --no-plot --out " + out,
                                         out + ".checkpoint", sig),
        &log);
    EXPECT_EQ(status, 130) << log;
    EXPECT_NE(log.find("interrupted"), std::string::npos) << log;
    EXPECT_NE(log.find("rover montecarlo --study " + study + " --checkpoint-every 1 --no-plot --out " + out + " --resume"),
              std::string::npos) << log;
    EXPECT_FALSE(std::ifstream(out).good()) << "no result file after an interrupt";
    EXPECT_TRUE(std::ifstream(out + ".checkpoint").good());
  }
}

// Ctrl-C of mpirun: Open MPI 4.1 sends the ranks SIGTERM one second later
// and SIGKILL one second after that, and MPI_Finalize no longer returns.
// Whatever finished must be in the checkpoint by then (the policy here
// flushes every 20 runs; the interrupt comes once the first 20 are saved),
// the resume hint must be printed, and the resumed study must equal an
// uninterrupted one bit for bit.
TEST(CmdStudies, InterruptOfMpirunSavesTheCheckpointAndResumesToTheSameResult) {
  const std::string dir = rover::testing::temp_dir();
  // Enough runs (several seconds on 2 ranks) that the interrupt, sent once the
  // first 20 are saved, lands while the study runs.
  constexpr int kRuns = 600;
  const std::string study = mc_study(dir, 1.0, kRuns);
  std::string log;
  ASSERT_EQ(run_command(mpiexec() + " -np 2 " + rover_binary() + " montecarlo --study " + study +
                            " --no-plot --out " + dir + "/whole.h5", &log), 0) << log;
  const std::string out = dir + "/part.h5";
  const int status = run_command("cd " + dir + " && " +
                                     signal_once_checkpoint_grows(mpiexec() + " -np 2 " + rover_binary() +
                                                                      " montecarlo --study " + study +
                                                                      " --checkpoint-every 20 --no-plot --out " + out,
                                                                  out + ".checkpoint", "INT"),
                                 &log);
  ASSERT_FALSE(std::ifstream(out).good()) << "the study finished before the interrupt: " << log;
  EXPECT_NE(status, 0) << log;  // mpirun's own status (1 with Open MPI 4.1), not the ranks'
  EXPECT_NE(log.find("interrupt"), std::string::npos) << log;
  EXPECT_NE(log.find("rover montecarlo --study " + study + " --checkpoint-every 20 --no-plot --out " + out + " --resume"),
            std::string::npos) << log;
  ASSERT_TRUE(std::ifstream(out + ".checkpoint").good()) << log;
  ASSERT_EQ(run_command(mpiexec() + " -np 2 " + rover_binary() + " montecarlo --study " + study +
                            " --no-plot --resume --out " + out, &log), 0) << log;
  const std::size_t pos = log.find("resuming, ");
  ASSERT_NE(pos, std::string::npos) << log;
  const int reused = std::stoi(log.substr(pos + 10));
  EXPECT_GT(reused, 20) << log;  // the runs finished after the interrupt were saved too
  EXPECT_LT(reused, kRuns) << log;
  const io::Hdf5Reader a(dir + "/whole.h5"), b(out);
  for (const std::string& name : kMonteCarloDatasets) EXPECT_EQ(a.read_doubles(name), b.read_doubles(name)) << name;
  EXPECT_EQ(a.read_ints("/samples/status"), b.read_ints("/samples/status"));
}

TEST(CmdStudies, AnOutputPathThatCannotBeWrittenIsRefusedBeforeAnyRun) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = mc_study(dir, 1.0, 3);
  for (const std::string& out : {dir, dir + "/x.txt", std::string("/proc/rover_cannot/x.h5")}) {
    std::string log;
    EXPECT_NE(run_command(rover_binary() + " montecarlo --study " + study + " --no-plot --out " + out, &log), 0) << out;
    EXPECT_NE(log.find(out), std::string::npos) << log;
    EXPECT_EQ(log.find("montecarlo: 0/"), std::string::npos) << "no run may start: " << log;
  }
}

TEST(CmdStudies, OneSummaryFigureByDefaultAndEveryFigureOnRequest) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot is not installed";
  const std::string dir = rover::testing::temp_dir();
  const std::string study = mc_study(dir, 1.0, 6);
  const auto pngs = [&](const std::string& stem) {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (name.starts_with(stem + "_") && name.ends_with(".png")) names.push_back(name);
    }
    std::sort(names.begin(), names.end());
    return names;
  };
  std::string log;
  for (const char* plots : {"summary", "all", "none"}) {
    const std::string stem = std::string("p_") + plots;
    const std::string flag = std::string(plots) == "summary" ? "" : std::string(" --plots ") + plots;
    ASSERT_EQ(run_command(rover_binary() + " montecarlo --study " + study + flag + " --out " + dir + "/" + stem + ".h5",
                          &log), 0) << log;
  }
  EXPECT_EQ(pngs("p_summary"), std::vector<std::string>{"p_summary_summary.png"});
  const std::vector<std::string> all = pngs("p_all");
  EXPECT_NE(std::find(all.begin(), all.end(), "p_all_summary.png"), all.end());
  EXPECT_NE(std::find(all.begin(), all.end(), "p_all_band_B_l_z.png"), all.end());
  EXPECT_NE(std::find(all.begin(), all.end(), "p_all_hist_deflection.png"), all.end());
  EXPECT_TRUE(pngs("p_none").empty());
}

TEST(CmdStudies, EveryRunFailingIsAnErrorButTheResultsAreKept) {
  // A wall-time budget of a microsecond: every run stops at its first steps.
  const std::string dir = rover::testing::temp_dir();
  const std::string scenario = write_file(dir + "/no_time.json", R"({"name": "no_time", "rover": ")" +
                                                                     source_path("configs/rover.json") +
                                                                     R"(", "duration": 0.25, "output_rate": 200,
      "wall_time_budget": 1e-6, "initial_q": {"z": 0.281, "chi": 0.039, "psi": 0.0042}})");
  const std::string path = dir + "/all_fail.json";
  write_file(path, R"({"type": "montecarlo", "name": "f", "scenario": ")" + scenario + R"(",
      "parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.2}},
      "design": {"type": "monte_carlo", "samples": 3}, "qoi": ["t_min"]})");
  std::string log;
  EXPECT_EQ(run_command(rover_binary() + " montecarlo --study " + path + " --no-plot --out " + dir + "/f.h5", &log), 2) << log;
  EXPECT_NE(log.find("every run failed"), std::string::npos) << log;
  const io::Hdf5Reader h5(dir + "/f.h5");
  const int budget = static_cast<int>(SimulationStatus::kTimeBudgetExceeded);
  EXPECT_EQ(h5.read_ints("/samples/status"), (std::vector<int>{budget, budget, budget}));
}

// Every standard deviation zero: every run would be the same run, whose band
// says nothing of uncertainty. Refused before any run, nothing written.
TEST(CmdStudies, EveryStandardDeviationZeroIsRefused) {
  const std::string dir = rover::testing::temp_dir();
  std::string log;
  EXPECT_EQ(run_command(rover_binary() + " montecarlo --study " + mc_study(dir, 0.0, 3) +
                            " --no-plot --out " + dir + "/mc0.h5", &log), 1) << log;
  EXPECT_NE(log.find("every parameter is fixed"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(dir + "/mc0.h5"));
}

TEST(CmdStudies, RejectedSamplesAreRecordedNeverRun) {
  // A preload sd 15 times the configured one draws negative preloads, which
  // the rover file's validation refuses: those runs are recorded as rejected
  // with the reason, the rest run.
  const std::string dir = rover::testing::temp_dir();
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " montecarlo --study " + mc_study(dir, 15.0, 12) + " --no-plot --out " +
                            dir + "/wide.h5", &log), 0) << log;
  const io::Hdf5Reader h5(dir + "/wide.h5");
  const auto status = h5.read_ints("/samples/status");
  const auto messages = h5.read_strings("/samples/message");
  const Eigen::MatrixXd x = h5.read_matrix("/inputs/values");
  int rejected = 0;
  for (std::size_t i = 0; i < status.size(); ++i) {
    const bool negative = x.row(static_cast<Eigen::Index>(i)).minCoeff() < 0.0;
    EXPECT_EQ(status[i] == 10, negative) << i << ": " << messages[i];
    if (negative) {
      ++rejected;
      EXPECT_NE(messages[i].find("preload"), std::string::npos) << messages[i];
    }
  }
  EXPECT_GT(rejected, 0);
  EXPECT_LT(rejected, 12);
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

TEST(CmdStudies, PceSensitivityOfIshigamiOnTwoRanksMatchesTheExactIndices) {
  // Exact S1 = (0.3139, 0.4424, 0), ST = (0.5576, 0.4424, 0.2437) (Ishigami, a = 7, b = 0.1).
  const std::string dir = rover::testing::temp_dir();
  const std::string path = dir + "/pce_ishigami.json";
  write_file(path, R"({"type": "sensitivity", "method": "pce", "name": "p", "model": "ishigami",
      "design": {"type": "lhs", "samples": 500, "seed": 11}, "pce": {"max_degree": 14, "bootstrap": 50}})");
  std::string log;
  ASSERT_EQ(run_command(mpiexec() + " -np 2 " + rover_binary() + " sensitivity --study " + path + " --no-plot --out " +
                            dir + "/pce.h5", &log), 0) << log;
  const io::Hdf5Reader h5(dir + "/pce.h5");
  EXPECT_EQ(h5.attribute_string("/", "method"), "pce");
  const std::vector<double> exact_S1{0.3139, 0.4424, 0.0}, exact_ST{0.5576, 0.4424, 0.2437};
  const auto S1 = h5.read_doubles("/indices/y/S1"), ST = h5.read_doubles("/indices/y/ST");
  ASSERT_EQ(S1.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(S1[i], exact_S1[i], 0.01) << i;
    EXPECT_NEAR(ST[i], exact_ST[i], 0.01) << i;
  }
  EXPECT_GT(h5.read_doubles("/pce/y/q2_loo").at(0), 0.99);
  EXPECT_EQ(h5.shape("/pce/y/multi_indices").at(1), 3u);
  EXPECT_NE(log.find("Q2_LOO"), std::string::npos) << log;
}

TEST(CmdStudies, PceWithTooFewRunsIsRefusedBeforeAnyRun) {
  const std::string dir = rover::testing::temp_dir();
  const std::string path = dir + "/pce_few.json";
  write_file(path, R"({"type": "sensitivity", "method": "pce", "name": "p", "model": "ishigami",
      "design": {"samples": 100}})");
  std::string log;
  EXPECT_NE(run_command(rover_binary() + " sensitivity --study " + path + " --samples 3 --no-plot --out " + dir +
                            "/few.h5", &log), 0);
  EXPECT_NE(log.find("needs at least"), std::string::npos) << log;
  EXPECT_EQ(log.find("runs (0 failed)"), std::string::npos) << "no run may start: " << log;
}

TEST(CmdStudies, BadStudyConfigsNameTheField) {
  const std::string dir = rover::testing::temp_dir();
  const std::string scenario = short_drop(dir);
  struct Case { std::string command, json, expected; };
  const std::vector<Case> cases{
      {"montecarlo", R"({"type": "montecarlo", "name": "m", "scenario": ")" + scenario + R"(", "parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.2}}, "qoi": ["t_min"], "design": {"type": "sobol", "samples": 0, "seed": 1}})", "design.samples"},
      {"montecarlo", R"({"type": "montecarlo", "name": "m", "scenario": ")" + scenario + R"(", "parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.2}}, "qoi": ["t_min"], "design": {"type": "sobol", "samples": 4294967298, "seed": 1}})", "design.samples"},
      {"montecarlo", R"({"type": "montecarlo", "name": "m", "scenario": ")" + scenario + R"(", "parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.2}}, "qoi": ["t_min"], "design": {"type": "sobol", "samples": 3, "seed": 1}, "sampels": 2})", "sampels"},
      {"montecarlo", R"({"type": "montecarlo", "name": "m", "scenario": ")" + scenario + R"(", "parameters": {"c_qq": {"distribution": "uniform", "min": 0.1, "max": 0.2}}, "qoi": ["t_min"], "design": {"type": "sobol", "samples": 3}})", "parameters.c_qq"},
      {"montecarlo", R"({"type": "montecarlo", "name": "m", "scenario": ")" + scenario + R"(", "parameters": {"c_q": {"distribution": "uniform", "min": 0.3, "max": 0.2}}, "qoi": ["t_min"], "design": {"type": "sobol", "samples": 3}})", "parameters.c_q.max"},
      {"montecarlo", R"({"type": "montecarlo", "name": "m", "scenario": ")" + scenario + R"(", "parameters": {"c_q": {"distribution": "gaussian", "mean": 0.2, "sd": 0.01}}, "qoi": ["t_min"], "design": {"type": "sobol", "samples": 3}})", "parameters.c_q.distribution"},
      {"montecarlo", R"({"type": "montecarlo", "name": "m", "scenario": ")" + scenario + R"(", "parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.2}}, "qoi": ["t_minimum"], "design": {"type": "sobol", "samples": 3}})", "qoi[0]"},
      {"montecarlo", R"({"type": "montecarlo", "name": "../m", "scenario": ")" + scenario + R"(", "parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.2}}, "qoi": ["t_min"], "design": {"type": "sobol", "samples": 3}})", "name"},
      {"surface", R"({"type": "surface", "name": "s", "scenario": ")" + scenario + R"(", "reference": {"simulate": {}},
          "f": {"min": 1e3, "max": 1e4, "count": 0}, "c_q": {"min": 0.1, "max": 0.2, "count": 2}})", "f.count"},
      {"surface", R"({"type": "surface", "name": "s", "scenario": ")" + scenario + R"(", "reference": {"simulate": {}},
          "f": {"min": 1e4, "max": 1e3, "count": 2}, "c_q": {"min": 0.1, "max": 0.2, "count": 2}})", "f.max"},
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
