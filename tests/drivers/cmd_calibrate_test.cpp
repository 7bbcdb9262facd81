// End-to-end tests of `rover calibrate` through the built binary: the fit
// recovers the generating damping with t-based Gauss-Newton intervals, the
// posterior is identical on one and two ranks, and bad input is refused with
// a message naming the field or the file.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

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

// configs/data/drop_horizontal_synthetic.csv was made at c_q = 0.25 with
// 0.1 mm noise and a 0.05 s offset (see its header).
TEST(CmdCalibrate, FitRecoversTheGeneratingDampingWithGaussNewtonIntervals) {
  const std::string dir = rover::testing::temp_dir();
  // The shipped study with the stiff integrator (seconds instead of a minute).
  const std::string study = write_file(dir + "/fit.json", R"({"type": "calibration", "name": "c", "scenario": ")" +
      source_path("configs/scenarios/drop_horizontal.json") + R"(", "integrator": {"method": "rosenbrock"},
      "data": ")" + source_path("configs/data/drop_horizontal_synthetic.csv") + R"(", "fit": ["c_q"],
      "bounds": {"c_q": [0.02, 1.0], "time_offset": [-0.2, 0.2]}, "initial": {"c_q": 0.1}, "max_evaluations": 30})");
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " calibrate --study " + study +
                            " --algorithm LN_BOBYQA --profile --no-plot --out " + dir + "/cal.h5", &log),
            0) << log;
  const io::Hdf5Reader h5(dir + "/cal.h5");
  const double c_q = h5.read_doubles("/best/values").at(0);
  EXPECT_NEAR(c_q, 0.25, 0.05 * 0.25) << log;
  EXPECT_NEAR(h5.read_doubles("/best/time_offset").at(0), 0.05, 2e-3);
  EXPECT_GT(h5.shape("/history").at(0), 3u);
  // Gauss-Newton over (c_q, profiled time_offset).
  EXPECT_EQ(h5.read_strings("/best/names_uncertainty"), (std::vector<std::string>{"c_q", "time_offset"}));
  EXPECT_EQ(h5.shape("/best/covariance"), (std::vector<std::size_t>{2, 2}));
  const auto se = h5.read_doubles("/best/stderr"), lower = h5.read_doubles("/best/lower"),
             upper = h5.read_doubles("/best/upper"), correlation = h5.read_doubles("/best/correlation");
  EXPECT_GT(se[0], 0.0);
  EXPECT_LT(se[0], 0.01);
  EXPECT_LT(lower[0], c_q);
  EXPECT_GT(upper[0], c_q);
  // x -+ t_{n-2}(0.975) se with n = 501 data points: t = 1.96473.
  EXPECT_NEAR(upper[0] - c_q, 1.96473 * se[0], 1e-4 * se[0]);
  EXPECT_NEAR(c_q - lower[0], 1.96473 * se[0], 1e-4 * se[0]);
  EXPECT_DOUBLE_EQ(correlation[0], 1.0);
  EXPECT_NEAR(correlation[1], correlation[2], 1e-12);
  EXPECT_LT(std::abs(correlation[1]), 1.0);
  // The noise sd estimated from the residuals is the generating 0.1 mm.
  EXPECT_NEAR(h5.read_doubles("/best/noise_sd").at(0), 1e-4, 1e-5);
  // The least-squares polish converged, the integration check passed, and
  // the interval holds the generating value.
  EXPECT_EQ(h5.attribute_integer("/best", "converged"), 1) << log;
  EXPECT_EQ(h5.attribute_integer("/best", "intervals_valid"), 1) << log;
  for (double shift : h5.read_doubles("/best/integration_shift")) EXPECT_LE(std::abs(shift), 0.1) << log;
  EXPECT_LT(lower[0], 0.25);
  EXPECT_GT(upper[0], 0.25);
  // The profile of c_q: its grid and interval are written.
  EXPECT_EQ(h5.read_doubles("/profile/c_q/values").size(), 13u);
  EXPECT_EQ(h5.read_doubles("/profile/c_q/weighted_rss").size(), 13u);
  EXPECT_LT(h5.attribute_double("/profile/c_q", "lower"), h5.attribute_double("/profile/c_q", "upper"));
  EXPECT_NE(log.find("profile-likelihood interval"), std::string::npos) << log;
  EXPECT_NE(log.find("c_q = "), std::string::npos);
  EXPECT_NE(log.find("(95 %)"), std::string::npos) << log;
}

// A fit stopped by its iteration budget says so before any interval, writes
// its intervals flagged as not valid, and exits with status 2.
TEST(CmdCalibrate, FitThatDidNotConvergeIsFlaggedAndExitsTwo) {
  const std::string dir = rover::testing::temp_dir();
  std::string log;
  const int status = run_command(rover_binary() + " calibrate --study " +
                                     source_path("configs/studies/calibration.json") +
                                     " --fit c_q,f --max-iterations 1 --no-plot --out " + dir + "/cal.h5",
                                 &log);
  EXPECT_EQ(status, 2) << log;
  const std::size_t warning = log.find("NOT VALID");
  ASSERT_NE(warning, std::string::npos) << log;
  EXPECT_LT(warning, log.find("Gauss-Newton 95 % intervals")) << log;
  EXPECT_NE(log.find("NOT CONVERGED"), std::string::npos) << log;
  const io::Hdf5Reader h5(dir + "/cal.h5");
  EXPECT_EQ(h5.attribute_integer("/best", "converged"), 0);
  EXPECT_EQ(h5.attribute_integer("/best", "intervals_valid"), 0);
  EXPECT_NE(h5.attribute_string("/best", "not_valid_because").find("did not converge"), std::string::npos);
}

// Any number of the rover file can be fitted by its dotted name: the S-joint
// stiffness k_q (log scale by default) beside c_q, from the synthetic drop
// made at c_q = 0.25 and the rover file's k_q = 9.91, started 30 % off.
TEST(CmdCalibrate, FitsAnyParameterByName) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = write_file(dir + "/kq.json", R"({"type": "calibration", "name": "kq", "scenario": ")" +
      source_path("configs/scenarios/drop_horizontal.json") + R"(", "data": ")" +
      source_path("configs/data/drop_horizontal_synthetic.csv") + R"(", "fit": ["c_q", "s_structure.k_q"],
      "bounds": {"c_q": [0.02, 1.0], "s_structure.k_q": [3, 30], "time_offset": [-0.2, 0.2]},
      "initial": {"c_q": 0.1, "s_structure.k_q": 13}})");
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " calibrate --study " + study + " --no-plot --out " + dir + "/kq.h5", &log),
            0) << log;
  const io::Hdf5Reader h5(dir + "/kq.h5");
  EXPECT_EQ(h5.read_strings("/best/names"), (std::vector<std::string>{"c_q", "s_structure.k_q"}));
  EXPECT_EQ(h5.attribute_integer("/best", "converged"), 1) << log;
  const auto lower = h5.read_doubles("/best/lower"), upper = h5.read_doubles("/best/upper");
  EXPECT_LT(lower[0], 0.25) << log;
  EXPECT_GT(upper[0], 0.25) << log;
  EXPECT_LT(lower[1], 9.91) << log;
  EXPECT_GT(upper[1], 9.91) << log;

  // A misspelt name is refused before any run, with the nearest names.
  EXPECT_EQ(run_command(rover_binary() + " calibrate --study " + study + " --fit s_structure.kq --out " + dir +
                            "/bad.h5", &log),
            1);
  EXPECT_NE(log.find("--fit"), std::string::npos) << log;
  EXPECT_NE(log.find("did you mean 's_structure.k_q'"), std::string::npos) << log;
}

// A horizontal drop synthesized on Dormand-Prince at rtol 1e-8 (not the
// stiff integrator the fit uses) with `options` (--cq, --f, --noise, ...),
// and a study fitting (c_q, f) to it with the defaults; returns the study.
std::string reference_drop_study(const std::string& dir, const std::string& options) {
  const std::string scenario = write_file(dir + "/reference_drop.json", R"({"name": "drop", "rover": ")" +
      source_path("configs/rover.json") + R"(", "duration": 1.0, "output_rate": 1000,
      "initial_q": {"z": 0.281, "chi": 0.039, "psi": 0.0042},
      "integrator": {"method": "dopri5", "rtol": 1e-8, "atol": 1e-11}})");
  std::string log;
  EXPECT_EQ(run_command(rover_binary() + " synthesize --scenario " + scenario + " " + options + " --out " + dir +
                            "/data.csv", &log),
            0) << log;
  return write_file(dir + "/study.json", R"({"type": "calibration", "name": "p", "scenario": ")" +
      source_path("configs/scenarios/drop_horizontal.json") + R"(", "data": ")" + dir + R"(/data.csv",
      "fit": ["c_q", "f"], "bounds": {"c_q": [0.02, 1.0], "f": [1e2, 1e5], "time_offset": [-0.2, 0.2]},
      "initial": {"c_q": 0.2, "f": 1e4}})");
}

// Precise data (1 kHz, 0.03 mm noise, made on Dormand-Prince at rtol 1e-8):
// the stiff integrator's default error moves c_q by several standard
// errors, so the integration check tightens it and refits until the shift
// is below 0.1 standard error; the intervals then hold the truths.
TEST(CmdCalibrate, IntegrationCheckTightensTheIntegratorUntilTheShiftIsSmall) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study =
      reference_drop_study(dir, "--cq 0.12 --f 8000 --noise 3e-5 --offset 0.021 --rate 1000 --seed 5");
  std::string log;
  ASSERT_EQ(run_command(mpiexec() + " -np 2 " + rover_binary() + " calibrate --study " + study +
                            " --no-plot --out " + dir + "/precise.h5", &log),
            0) << log;
  EXPECT_NE(log.find("refitting with rosenbrock"), std::string::npos) << log;
  const io::Hdf5Reader h5(dir + "/precise.h5");
  EXPECT_EQ(h5.attribute_integer("/best", "intervals_valid"), 1) << log;
  EXPECT_NE(h5.attribute_string("/best", "integrator"), "rosenbrock at rtol 1e-05, atol 0.0002");
  // The profile probe: near-quadratic at the 95 % ends (4 expected), no lower point.
  const auto rises = h5.read_doubles("/best/probe_delta_chi2");
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_GT(rises[8 * k + 2], 2.0) << log;
    EXPECT_GT(rises[8 * k + 5], 2.0) << log;
  }
  for (double shift : h5.read_doubles("/best/integration_shift")) EXPECT_LE(std::abs(shift), 0.1) << log;
  const auto lower = h5.read_doubles("/best/lower"), upper = h5.read_doubles("/best/upper");
  EXPECT_LT(lower[0], 0.12) << log;
  EXPECT_GT(upper[0], 0.12) << log;
  EXPECT_LT(lower[1], 8000) << log;
  EXPECT_GT(upper[1], 8000) << log;
}

// A drop made at f = 5e4 (the S-joints' atan nearly saturated) sampled at
// 400 Hz with 0.16 mm noise: the objective is far from quadratic, and the
// profile probe flags the Gauss-Newton intervals as not valid (exit 2),
// naming the parameter, while the precise drop above passes.
TEST(CmdCalibrate, ProfileProbeFlagsAnObjectiveFlatterThanItsIntervals) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study =
      reference_drop_study(dir, "--cq 0.16 --f 50000 --noise 1.6e-4 --offset 0.03 --rate 400 --seed 3");
  std::string log;
  EXPECT_EQ(run_command(mpiexec() + " -np 2 " + rover_binary() + " calibrate --study " + study + " --no-plot --out " +
                            dir + "/flat.h5", &log),
            2) << log;
  EXPECT_NE(log.find("NOT VALID: the objective is flatter than the Gauss-Newton intervals assume"), std::string::npos)
      << log;
  const io::Hdf5Reader h5(dir + "/flat.h5");
  EXPECT_EQ(h5.attribute_integer("/best", "converged"), 1) << log;
  EXPECT_EQ(h5.attribute_integer("/best", "intervals_valid"), 0) << log;
  EXPECT_EQ(h5.shape("/best/probe_delta_chi2"), (std::vector<std::size_t>{2, 8}));
  const auto rises = h5.read_doubles("/best/probe_delta_chi2");
  bool below_two_at_two_se = false;  // columns 2 and 5: -2 and +2 standard errors
  for (std::size_t k = 0; k < 2; ++k)
    below_two_at_two_se = below_two_at_two_se || rises[8 * k + 2] < 2.0 || rises[8 * k + 5] < 2.0;
  EXPECT_TRUE(below_two_at_two_se) << log;
}

// Ranking the next experiment: repeating the experiment just fitted (same
// drop, channel and rate, its noise) shrinks the interval by about 1 / sqrt 2
// (by 1 / sqrt(1 + (s / sigma)^2), s the fitted noise sd); a 1 kHz curve with
// a third of the noise ranks first.
TEST(CmdCalibrate, NextExperimentRanksByExpectedIntervalWidth) {
  const std::string dir = rover::testing::temp_dir();
  const std::string candidates = write_file(dir + "/candidates.json", R"({"candidates": [
      {"name": "repeat", "scenario": ")" + source_path("configs/scenarios/drop_horizontal.json") + R"(",
       "rate_hz": 500, "noise_sd": 1e-4},
      {"name": "precise", "scenario": ")" + source_path("configs/scenarios/drop_horizontal.json") + R"(",
       "rate_hz": 1000, "noise_sd": 3e-5},
      {"name": "higher", "scenario": ")" + source_path("configs/scenarios/drop_horizontal.json") + R"(",
       "rate_hz": 500, "noise_sd": 1e-4, "set": {"scenario.initial_q.z": 0.301}}]})");
  std::string log;
  ASSERT_EQ(run_command(rover_binary() + " calibrate --study " + source_path("configs/studies/calibration.json") +
                            " --next-experiment " + candidates + " --out " + dir + "/next.h5", &log),
            0) << log;
  const io::Hdf5Reader h5(dir + "/next.h5");
  const auto names = h5.read_strings("/next_experiment/candidates");
  const auto score = h5.read_doubles("/next_experiment/score");
  ASSERT_EQ(names.size(), 3u);
  EXPECT_EQ(names[0], "precise") << log;
  for (std::size_t r = 0; r < names.size(); ++r)
    if (names[r] == "repeat") {
      EXPECT_GT(score[r], 0.65) << log;
      EXPECT_LT(score[r], 0.78) << log;
    }
  EXPECT_NE(log.find("ranked by the expected 95 % half-width"), std::string::npos) << log;

  // A candidate that names an unknown parameter is refused with the field.
  const std::string bad = write_file(dir + "/bad.json", R"({"candidates": [{"scenario": ")" +
      source_path("configs/scenarios/drop_horizontal.json") + R"(", "rate_hz": 500, "noise_sd": 1e-4,
      "set": {"scenario.initial_q.zz": 0.3}}]})");
  EXPECT_EQ(run_command(rover_binary() + " calibrate --study " + source_path("configs/studies/calibration.json") +
                            " --next-experiment " + bad + " --out " + dir + "/bad.h5", &log),
            1);
  EXPECT_NE(log.find("'candidates[0].set.scenario.initial_q.zz'"), std::string::npos) << log;
}

// A quick posterior's exit status: its few steps are too short for its
// autocorrelation time, so it is written flagged NOT VALID (status 2); a
// complete run of a valid one is 0. Either way the file holds the chains.
bool posterior_written(int status) { return status == 0 || status == 2; }

// A quick posterior: a 0.25 s drop with the stiff integrator, 4 walkers.
std::string mcmc_study(const std::string& dir, int walkers = 4, int steps = 6,
                       const std::string& sampler = "independence") {
  const std::string scenario = write_file(dir + "/short_drop.json", R"({"name": "short_drop", "rover": ")" +
      source_path("configs/rover.json") + R"(", "duration": 0.25, "output_rate": 200,
      "initial_q": {"z": 0.281, "chi": 0.039, "psi": 0.0042}})");
  // The shipped curve's first 0.3 s of data time: inside the 0.25 s run for offsets up to 0.05 s and beyond.
  std::ifstream full(source_path("configs/data/drop_horizontal_synthetic.csv"));
  std::ofstream cut(dir + "/short_data.csv");
  for (std::string line; std::getline(full, line);)
    if (line.empty() || line[0] == '#' || line[0] == 't' || std::stod(line) <= 0.3) cut << line << "\n";
  cut.close();
  return write_file(dir + "/mcmc.json", R"({"type": "calibration", "name": "m", "scenario": ")" + scenario +
      R"(", "integrator": {"method": "rosenbrock"}, "data": ")" + dir + R"(/short_data.csv", "method": "mcmc", "fit": ["c_q"],
      "bounds": {"c_q": [0.02, 1.0], "time_offset": [-0.2, 0.2]}, "initial": {"c_q": 0.25},
      "priors": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.5}},
      "mcmc": {"sampler": ")" + sampler + R"(", "walkers": )" + std::to_string(walkers) +
      R"(, "steps": )" + std::to_string(steps) + R"(, "discard": 2, "seed": 3, "predictive_draws": 4, "target_ess": 0,
               "noise_sd": {"distribution": "log_uniform", "min": 1e-5, "max": 1e-2}}})");
}

TEST(CmdCalibrate, PosteriorIsIdenticalOnOneAndTwoRanks) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = mcmc_study(dir);
  std::string log1, log2;
  ASSERT_TRUE(posterior_written(
      run_command(rover_binary() + " calibrate --study " + study + " --no-plot --out " + dir + "/np1.h5", &log1)))
      << log1;
  ASSERT_TRUE(posterior_written(run_command(mpiexec() + " -np 2 " + rover_binary() + " calibrate --study " + study +
                                                " --no-plot --out " + dir + "/np2.h5", &log2)))
      << log2;
  const io::Hdf5Reader a(dir + "/np1.h5"), b(dir + "/np2.h5");
  EXPECT_EQ(a.shape("/chain"), (std::vector<std::size_t>{6, 4 * 2}));
  EXPECT_EQ(a.read_doubles("/chain"), b.read_doubles("/chain"));
  EXPECT_EQ(a.read_doubles("/log_posterior"), b.read_doubles("/log_posterior"));
  EXPECT_EQ(a.read_doubles("/predictive/upper"), b.read_doubles("/predictive/upper"));
  EXPECT_EQ(a.read_strings("/posterior/names"), (std::vector<std::string>{"c_q", "noise_sd"}));
  // Every sample is inside the prior's support.
  const auto chain = a.read_doubles("/chain");
  for (std::size_t i = 0; i < chain.size(); i += 2) {
    EXPECT_GE(chain[i], 0.1);
    EXPECT_LE(chain[i], 0.5);
    EXPECT_GT(chain[i + 1], 1e-5);
  }
  // The band holds its mean; with noise it is wider.
  const auto lower = a.read_doubles("/predictive/lower"), upper = a.read_doubles("/predictive/upper"),
             mean = a.read_doubles("/predictive/mean"), lower_noise = a.read_doubles("/predictive/lower_noise"),
             upper_noise = a.read_doubles("/predictive/upper_noise");
  for (std::size_t i = 0; i < mean.size(); ++i) {
    EXPECT_LE(lower[i], mean[i]);
    EXPECT_GE(upper[i], mean[i]);
    EXPECT_GT(upper_noise[i] - lower_noise[i], upper[i] - lower[i]);
  }
  EXPECT_NE(log1.find("WARNING"), std::string::npos) << log1;  // 6 steps: loudly unreliable
}

// A prior far wider than the bounds (normal(0.25, 5) on c_q in [0.02, 1]):
// both samplers keep every sample inside the bounds (the prior is truncated
// there, and a point outside is rejected without a run) and finish.
TEST(CmdCalibrate, WidePriorIsTruncatedToTheBounds) {
  for (const std::string sampler : {"independence", "ensemble"}) {
    const std::string dir = rover::testing::temp_dir();
    std::string text;
    {
      std::ifstream in(mcmc_study(dir, 4, 12, sampler));
      text.assign(std::istreambuf_iterator<char>(in), {});
    }
    const std::string uniform = R"({"distribution": "uniform", "min": 0.1, "max": 0.5})";
    text.replace(text.find(uniform), uniform.size(), R"({"distribution": "normal", "mean": 0.25, "sd": 5})");
    const std::string study = write_file(dir + "/wide.json", text);
    std::string log;
    ASSERT_TRUE(posterior_written(
        run_command(rover_binary() + " calibrate --study " + study + " --no-plot --out " + dir + "/w.h5", &log)))
        << sampler << "\n" << log;
    const auto chain = io::Hdf5Reader(dir + "/w.h5").read_doubles("/chain");
    for (std::size_t i = 0; i < chain.size(); i += 2) {
      EXPECT_GE(chain[i], 0.02) << sampler;
      EXPECT_LE(chain[i], 1.0) << sampler;
    }
  }
}

TEST(CmdCalibrate, KilledPosteriorResumesToTheUninterruptedChain) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = mcmc_study(dir, 8, 30);
  std::string log;
  ASSERT_TRUE(posterior_written(
      run_command(rover_binary() + " calibrate --study " + study + " --no-plot --out " + dir + "/whole.h5", &log)))
      << log;
  // SIGKILL once some steps are checkpointed (the ensemble is saved every step).
  run_command("cd " + dir + " && " +
                  signal_once_checkpoint_grows(rover_binary() + " calibrate --study " + study + " --no-plot --out " +
                                                   dir + "/part.h5",
                                               dir + "/part.h5.checkpoint", "KILL"),
              &log);
  ASSERT_FALSE(std::ifstream(dir + "/part.h5").good()) << "the study finished before the kill: " << log;
  ASSERT_TRUE(std::ifstream(dir + "/part.h5.checkpoint").good()) << log;
  ASSERT_TRUE(posterior_written(run_command(rover_binary() + " calibrate --study " + study +
                                                " --no-plot --resume --out " + dir + "/part.h5", &log)))
      << log;
  EXPECT_NE(log.find("resuming the chains after step"), std::string::npos) << log;
  const io::Hdf5Reader whole(dir + "/whole.h5"), part(dir + "/part.h5");
  EXPECT_EQ(whole.read_doubles("/chain"), part.read_doubles("/chain"));
  EXPECT_EQ(whole.read_doubles("/log_posterior"), part.read_doubles("/log_posterior"));
  EXPECT_EQ(whole.read_doubles("/predictive/lower_noise"), part.read_doubles("/predictive/lower_noise"));
  EXPECT_FALSE(std::ifstream(dir + "/part.h5.checkpoint").good());
}

TEST(CmdCalibrate, BadInputIsRefusedNamingTheFieldOrFile) {
  const std::string dir = rover::testing::temp_dir();
  const std::string backwards = write_file(dir + "/backwards.csv", "t,z\n0,0.25\n0.2,0.24\n0.1,0.23\n");
  const std::string two_rows = write_file(dir + "/two_rows.csv", "t,z\n0,0.25\n0.1,0.24\n");
  struct Case {
    std::string options, expected;
  };
  const std::vector<Case> cases{
      {"--starts 0", "--starts must be from 1 to 100000, got 0"},
      {"--max-evaluations -1", "--max-evaluations must be from 1 to 100000000, got -1"},
      {"--algorithm LD_MMA", "--algorithm: 'LD_MMA' needs gradients"},
      {"--data " + backwards, backwards},
      {"--data " + two_rows, two_rows},
      {"--method mcmc --walkers 2", "--walkers: got 2"},
      {"--fit c_q,stiffness", "--fit: unknown parameter 'stiffness'"},
  };
  for (const Case& c : cases) {
    std::string log;
    EXPECT_NE(run_command("cd " + source_path("") + " && " + rover_binary() + " calibrate " + c.options +
                              " --no-plot --out " + dir + "/bad.h5", &log), 0) << c.options;
    EXPECT_NE(log.find(c.expected), std::string::npos) << c.options << "\n" << log;
  }
  // Reversed bounds in the study file.
  const std::string study = write_file(dir + "/bad.json", R"({"type": "calibration", "name": "c", "scenario": ")" +
      source_path("configs/scenarios/drop_horizontal.json") + R"(", "data": ")" +
      source_path("configs/data/drop_horizontal_synthetic.csv") + R"(", "fit": ["c_q"],
      "bounds": {"c_q": [1.0, 0.1]}, "initial": {"c_q": 0.5}})");
  std::string log;
  EXPECT_NE(run_command(rover_binary() + " calibrate --study " + study + " --no-plot --out " + dir + "/bad.h5", &log), 0);
  EXPECT_NE(log.find(study), std::string::npos) << log;
  EXPECT_NE(log.find("'bounds.c_q'"), std::string::npos) << log;

  // A bound the model does not accept (negative damping) is refused before any run.
  const std::string negative = write_file(dir + "/negative.json", R"({"type": "calibration", "name": "c",
      "scenario": ")" + source_path("configs/scenarios/drop_horizontal.json") + R"(", "data": ")" +
      source_path("configs/data/drop_horizontal_synthetic.csv") + R"(", "fit": ["c_q"],
      "bounds": {"c_q": [-0.1, 1.0]}, "initial": {"c_q": 0.5}})");
  EXPECT_EQ(run_command(rover_binary() + " calibrate --study " + negative + " --no-plot --out " + dir + "/neg.h5", &log),
            1);
  EXPECT_NE(log.find("c_q: the bound -0.1 is not a valid value"), std::string::npos) << log;
  EXPECT_NE(log.find("must not be negative"), std::string::npos) << log;
  EXPECT_EQ(log.find("Jacobian"), std::string::npos) << "refused only after runs:\n" << log;
}

// The shipped curve's release is at 0.05 s on the data clock; offset bounds
// that exclude it leave the fitted offset on its bound, and the intervals
// are flagged (exit 2) with the bound to widen.
TEST(CmdCalibrate, AnOffsetOnItsBoundIsFlagged) {
  const std::string dir = rover::testing::temp_dir();
  const std::string study = write_file(dir + "/offset.json", R"({"type": "calibration", "name": "c",
      "scenario": ")" + source_path("configs/scenarios/drop_horizontal.json") + R"(", "data": ")" +
      source_path("configs/data/drop_horizontal_synthetic.csv") + R"(", "fit": ["c_q"],
      "bounds": {"c_q": [0.02, 1.0], "time_offset": [0.06, 0.2]}, "initial": {"c_q": 0.2}})");
  std::string log;
  EXPECT_EQ(run_command(rover_binary() + " calibrate --study " + study + " --no-plot --out " + dir + "/o.h5", &log), 2)
      << log;
  EXPECT_NE(log.find("time_offset = 0.06 is on its bound (widen bounds.time_offset)"), std::string::npos) << log;
  EXPECT_EQ(io::Hdf5Reader(dir + "/o.h5").attribute_integer("/best", "intervals_valid"), 0) << log;
}

// Data that end before the wheels touch the ground say nothing about the
// damping: its column of the Jacobian is zero, and the fit must say that the
// data do not determine it instead of printing an interval.
TEST(CmdCalibrate, DataThatCannotDetermineAParameterAreFlagged) {
  const std::string dir = rover::testing::temp_dir();
  std::ifstream full(source_path("configs/data/drop_horizontal_synthetic.csv"));
  std::string free_fall;  // released at 0.05 s of the data clock, first contact about 0.09 s later
  for (std::string line; std::getline(full, line);) {
    double t = 0.0;
    if (std::sscanf(line.c_str(), "%lf,", &t) == 1 && line[0] != '#' && t > 0.12) break;
    free_fall += line + "\n";
  }
  write_file(dir + "/free_fall.csv", free_fall);
  const std::string study = write_file(dir + "/free.json", R"({"type": "calibration", "name": "c",
      "scenario": ")" + source_path("configs/scenarios/drop_horizontal.json") + R"(", "data": "free_fall.csv",
      "fit": ["c_q"], "bounds": {"c_q": [0.02, 1.0], "time_offset": [0.0, 0.1]}})");
  std::string log;
  EXPECT_EQ(run_command(rover_binary() + " calibrate --study " + study + " --no-plot --out " + dir + "/f.h5", &log), 2)
      << log;
  EXPECT_NE(log.find("the data do not determine c_q"), std::string::npos) << log;
  EXPECT_EQ(io::Hdf5Reader(dir + "/f.h5").attribute_integer("/best", "intervals_valid"), 0) << log;
}

}  // namespace
}  // namespace rover
