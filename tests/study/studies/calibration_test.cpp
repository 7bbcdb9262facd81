// Calibration (study/studies/calibration.cpp, study/studies/calibration_mcmc.cpp): the time
// offset, the Gaussian likelihood and the posterior against closed forms, and
// the study file's checks; and the regression of the response-surface sweep
// (study/studies/surface.cpp).
#include "study/studies/calibration.hpp"

#include <cmath>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/json_reader.hpp"
#include "study/studies/calibration_mcmc.hpp"
#include "study/estimators/ensemble_sampler.hpp"
#include "test_support.hpp"

namespace rover::study {
namespace {

TEST(Calibration, BestOffsetRecoversAKnownShift) {
  // A drop-like curve: constant, a smooth dip, constant.
  std::vector<double> t, z;
  for (int k = 0; k <= 1000; ++k) {
    t.push_back(k * 1e-3);
    z.push_back(0.25 - 0.05 * std::exp(-std::pow((t.back() - 0.3) / 0.08, 2)));
  }
  const double offset = 0.0437;
  std::vector<double> td, zd;
  for (int k = 0; k <= 400; ++k) {
    td.push_back(k * 2.5e-3);
    zd.push_back(0.25 - 0.05 * std::exp(-std::pow((td.back() - offset - 0.3) / 0.08, 2)));
  }
  const double found = best_offset(t, z, td, zd, -0.2, 0.2);
  EXPECT_NEAR(found, offset, 2e-5);
  EXPECT_LT(shifted_rms(t, z, td, zd, found), 1e-5);
  EXPECT_GT(shifted_rms(t, z, td, zd, 0.0), 1e-3);
  // The residuals are the RMS's terms.
  const std::vector<double> r = shifted_residuals(t, z, td, zd, 0.0);
  double ss = 0;
  for (double v : r) ss += v * v;
  EXPECT_NEAR(std::sqrt(ss / static_cast<double>(r.size())), shifted_rms(t, z, td, zd, 0.0), 1e-15);
}

TEST(Calibration, GaussianLogLikelihoodIsTheNormalDensity) {
  // Two residuals 0.1 and -0.2 with sd 0.5: sum of log N(r; 0, 0.25).
  const double sd = 0.5;
  double expected = 0;
  for (double r : {0.1, -0.2})
    expected += -0.5 * std::log(2 * std::numbers::pi * sd * sd) - r * r / (2 * sd * sd);
  EXPECT_NEAR(gaussian_log_likelihood({0.1, -0.2}, sd), expected, 1e-14);
  // Maximised over sd at the RMS: d/dsd = 0 there.
  const std::vector<double> r{0.3, -0.1, 0.2, 0.05};
  double ss = 0;
  for (double v : r) ss += v * v;
  const double rms = std::sqrt(ss / 4), h = 1e-6;
  EXPECT_GT(gaussian_log_likelihood(r, rms), gaussian_log_likelihood(r, rms * (1 + 1e-2)));
  EXPECT_GT(gaussian_log_likelihood(r, rms), gaussian_log_likelihood(r, rms * (1 - 1e-2)));
  EXPECT_NEAR((gaussian_log_likelihood(r, rms + h) - gaussian_log_likelihood(r, rms - h)) / (2 * h), 0.0, 1e-6);
}

TEST(Calibration, LogDensityOutsideThePriorSkipsTheModel) {
  int calls = 0;
  const ResidualFunction residuals = [&](const std::vector<double>&) {
    ++calls;
    return std::optional<std::vector<std::vector<double>>>(std::vector<std::vector<double>>{{0.0}});
  };
  const std::vector<Distribution> priors{uniform(0.0, 1.0)};
  EXPECT_EQ(calibration_log_density(priors, log_uniform(1e-3, 1.0), std::nullopt, 1, Eigen::Vector2d(1.5, 0.1), residuals),
            -std::numeric_limits<double>::infinity());
  EXPECT_EQ(calibration_log_density(priors, log_uniform(1e-3, 1.0), std::nullopt, 1, Eigen::Vector2d(0.5, 2.0), residuals),
            -std::numeric_limits<double>::infinity());
  EXPECT_EQ(calls, 0);
  // A failed model run is -inf too.
  EXPECT_EQ(calibration_log_density(priors, {}, 0.1, 1, Eigen::VectorXd::Constant(1, 0.5),
                                    [](const std::vector<double>&) { return std::optional<std::vector<std::vector<double>>>(); }),
            -std::numeric_limits<double>::infinity());
  // Inside: prior + likelihood.
  EXPECT_NEAR(calibration_log_density(priors, {}, 0.1, 1, Eigen::VectorXd::Constant(1, 0.5), residuals),
              std::log(1.0) + gaussian_log_likelihood({0.0}, 0.1), 1e-14);
  // Two curves, each with its own sampled noise sd: the sum of their likelihoods.
  const ResidualFunction two = [](const std::vector<double>&) {
    return std::optional<std::vector<std::vector<double>>>(std::vector<std::vector<double>>{{0.1, -0.1}, {0.3}});
  };
  EXPECT_NEAR(calibration_log_density(priors, log_uniform(1e-3, 1.0), std::nullopt, 2, Eigen::Vector3d(0.5, 0.2, 0.4), two),
              log_uniform(1e-3, 1.0).log_pdf(0.2) + log_uniform(1e-3, 1.0).log_pdf(0.4) +
                  gaussian_log_likelihood({0.1, -0.1}, 0.2) + gaussian_log_likelihood({0.3}, 0.4),
              1e-12);
}

// y_i = a + b x_i + e_i with known sd and a flat prior: the posterior is
// Normal((X^T X)^-1 X^T y, sd^2 (X^T X)^-1) (Gelman et al. 2013, section 14.2).
// Sampled through calibration_log_density and the ensemble sampler.
TEST(Calibration, LinearGaussianPosteriorMatchesTheClosedForm) {
  const int n = 20;
  const double sd = 0.3;
  Eigen::MatrixXd X(n, 2);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    const double x = -1.0 + 2.0 * i / (n - 1);
    X(i, 0) = 1.0;
    X(i, 1) = x;
    y[i] = 0.7 - 1.3 * x + sd * std::sin(7.0 * i);  // fixed "noise"
  }
  const Eigen::Matrix2d precision = X.transpose() * X;
  const Eigen::Vector2d mean = precision.ldlt().solve(X.transpose() * y);
  const Eigen::Matrix2d covariance = sd * sd * precision.inverse();

  const std::vector<Distribution> priors{uniform(-20, 20), uniform(-20, 20)};
  const BatchLogDensity batch = [&](const DesignMatrix& points) {
    Eigen::VectorXd lp(points.rows());
    for (Eigen::Index w = 0; w < points.rows(); ++w)
      lp[w] = calibration_log_density(priors, {}, sd, 1, points.row(w).transpose(), [&](const std::vector<double>& ab) {
        std::vector<double> r(n);
        for (int i = 0; i < n; ++i) r[i] = ab[0] + ab[1] * X(i, 1) - y[i];
        return std::optional<std::vector<std::vector<double>>>(std::vector<std::vector<double>>{r});
      });
    return lp;
  };
  const int walkers = 16;
  DesignMatrix start(walkers, 2);
  for (int w = 0; w < walkers; ++w) {
    start(w, 0) = 0.1 * std::cos(w);
    start(w, 1) = 0.1 * std::sin(3.0 * w);
  }
  const EnsembleChain chain =
      run_ensemble(initial_ensemble_state(start, batch), batch, {.walkers = walkers, .seed = 42}, 3000);
  const long burn = 500;
  for (int k = 0; k < 2; ++k) {
    const Eigen::MatrixXd kept = chain.samples[k].bottomRows(3000 - burn);
    const double m = kept.mean();
    const double s = std::sqrt((kept.array() - m).square().mean());
    const double exact_sd = std::sqrt(covariance(k, k));
    // ~40000 draws with tau ~ 30 steps: ESS ~ 1300, so the mean is known to
    // ~ 0.03 sd and the sd to ~ 2 %.
    EXPECT_NEAR(m, mean[k], 0.15 * exact_sd) << k;
    EXPECT_NEAR(s, exact_sd, 0.08 * exact_sd) << k;
  }
}

// Every channel a measured curve may be is a height of study/model/qoi.hpp, in
// metres (the data's unit); the names are the study file's.
TEST(Calibration, ChannelsAreTheHeightChannels) {
  std::vector<std::string> names;
  for (const CalibrationChannel& c : calibration_channels()) {
    names.push_back(c.name);
    EXPECT_EQ(c.name, channel_name(c.channel));
    EXPECT_STREQ(channel_unit(c.channel), "m") << c.name;
    EXPECT_EQ(&calibration_channel(c.name), &c);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"B_l_z", "B_r_z", "G_z"}));
  try {
    (void)calibration_channel("pitch");
    ADD_FAILURE() << "pitch (radians) accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "unknown channel 'pitch' (valid: B_l_z, B_r_z, G_z)");
  }
}

// --- the study file's checks -------------------------------------------------

std::string write_file(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::string study_text(const std::string& data, const std::string& extra = "") {
  return R"({"type": "calibration", "name": "c", "scenario": ")" +
         rover::testing::source_path("configs/scenarios/drop_horizontal.json") + R"(", "data": ")" + data +
         R"(", "fit": ["c_q"], "bounds": {"c_q": [0.02, 1.0]}, "initial": {"c_q": 0.1})" + extra + "}";
}

// Loading must fail with a ConfigError whose message names the field.
void expect_refused(const std::string& path, const std::string& field, const CalibrationOverrides& o = {}) {
  try {
    load_calibration_study(path, o);
    ADD_FAILURE() << "accepted; expected an error naming " << field;
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(Calibration, StudyFileChecksNameTheField) {
  const std::string dir = rover::testing::temp_dir();
  const std::string good = rover::testing::source_path("configs/data/drop_horizontal_synthetic.csv");
  const std::string study = write_file(dir, "good.json", study_text(good));
  const CalibrationStudy s = load_calibration_study(study);
  ASSERT_EQ(s.datasets.size(), 1u);
  EXPECT_EQ(s.datasets[0].t.size(), 501u);
  EXPECT_EQ(s.datasets[0].channel, "B_l_z");
  EXPECT_EQ(s.method, CalibrationMethod::optimize);

  // Bad data: the checks of `rover compare`.
  const std::string one_row = write_file(dir, "one_row.csv", "t,z\n0,0.25\n");
  const std::string empty = write_file(dir, "empty.csv", "t,z\n");
  const std::string backwards = write_file(dir, "backwards.csv", "t,z\n0,0.25\n0.2,0.24\n0.1,0.23\n");
  const std::string duplicate = write_file(dir, "duplicate.csv", "t,z\n0,0.25\n0.1,0.24\n0.1,0.23\n");
  const std::string huge = write_file(dir, "huge.csv", "t,z\n0,0.25\n0.1,1e300\n0.2,0.23\n");
  for (const std::string& data : {one_row, empty, backwards, duplicate, huge})
    expect_refused(write_file(dir, "bad_data.json", study_text(data)), data);

  // Bad options.
  expect_refused(write_file(dir, "a.json", study_text(good, R"(, "algorithm": "LD_LBFGS")")), "'algorithm'");
  expect_refused(write_file(dir, "b.json", study_text(good, R"(, "starts": 0)")), "'starts'");
  expect_refused(write_file(dir, "c.json", study_text(good, R"(, "max_evaluations": -1)")), "'max_evaluations'");
  // An override's error names its flag, not the study file's field.
  expect_refused(study, "--starts: must be positive, got 0", {.starts = 0});
  expect_refused(study, "--max-evaluations: must be positive, got -1", {.max_evaluations = -1});
  expect_refused(study, "--algorithm: 'GD_STOGO' needs gradients", {.algorithm = "GD_STOGO"});
  expect_refused(study, "--walkers: got 2", {.method = "mcmc", .walkers = 2});
  expect_refused(write_file(dir, "d.json", study_text(good, R"(, "priors": {"c_q": {"distribution": "uniform", "min": 0.5, "max": 0.1}})")),
                 "'priors.c_q");
  expect_refused(write_file(dir, "e.json", study_text(good, R"(, "method": "mcmc", "mcmc": {"walkers": 2})")),
                 "'mcmc.walkers'");
  // c_q and the noise sd are sampled: 4 walkers at least, and the message says why.
  expect_refused(write_file(dir, "e.json", study_text(good, R"(, "method": "mcmc", "mcmc": {"walkers": 2})")),
                 "got 2; must be even and at least 4, twice the 2 sampled parameters (c_q, noise_sd)");
  expect_refused(write_file(dir, "e.json", study_text(good, R"(, "method": "mcmc", "mcmc": {"walkers": 5})")),
                 "got 5; must be even");
  EXPECT_EQ(load_calibration_study(write_file(dir, "e.json", study_text(good, R"(, "method": "mcmc", "mcmc": {"walkers": 4})")))
                .mcmc.walkers, 4);
  expect_refused(write_file(dir, "f.json", study_text(good, R"(, "method": "nuts")")), "'method'");
  // Data the run cannot use: a constant curve, and data past the simulated end.
  const std::string constant = write_file(dir, "constant.csv", "t,z\n0,0.25\n0.1,0.25\n0.2,0.25\n0.3,0.25\n");
  expect_refused(write_file(dir, "k1.json", study_text(constant)), "constant");
  const std::string long_data = write_file(dir, "long.csv", "t,z\n0,0.25\n1,0.24\n2,0.23\n5,0.2\n");
  expect_refused(write_file(dir, "k2.json", study_text(long_data)), "past the end of the simulated 1 s");
  // "accuracy" in metres chooses the integrator; outside (1e-12, 1e-2) m, or
  // beside "integrator", it is refused naming the field.
  const CalibrationStudy accurate = load_calibration_study(write_file(dir, "a1.json", study_text(good, R"(, "accuracy": 1e-6)")));
  EXPECT_FALSE(accurate.accuracy_choice.empty());
  EXPECT_LE(accurate.integrator.relative_tolerance, 1e-5);
  expect_refused(write_file(dir, "a2.json", study_text(good, R"(, "accuracy": 0.1)")), "'accuracy'");
  expect_refused(write_file(dir, "a3.json", study_text(good, R"(, "accuracy": 1e-6, "integrator": {"method": "dopri5"})")),
                 "not both");
  // Parameters: any name of the parameter space, checked before any run.
  auto with_fit = [&](const std::string& fit, const std::string& bounds, const std::string& initial) {
    return R"({"type": "calibration", "name": "c", "scenario": ")" +
           rover::testing::source_path("configs/scenarios/drop_horizontal.json") + R"(", "data": ")" + good +
           R"(", "fit": [")" + fit + R"("], "bounds": {")" + fit + R"(": )" + bounds + R"(}, "initial": {")" + fit +
           R"(": )" + initial + "}}";
  };
  expect_refused(write_file(dir, "p1.json", with_fit("contact.cg", "[1, 200]", "100")),
                 "did you mean 'contact.c_g'");
  expect_refused(write_file(dir, "p2.json", with_fit("contact.c_g", "[200, 1]", "100")), "'bounds.contact.c_g'");
  expect_refused(write_file(dir, "p3.json", with_fit("contact.c_g", "[1, 200]", "300")), "'initial.contact.c_g'");
  expect_refused(write_file(dir, "p4.json", with_fit("contact.k_g", "[-1, 1e7]", "1e6")), "positive bounds");
  expect_refused(write_file(dir, "p5.json", study_text(good, R"(, "priors": {"c_q": {"distribution": "normal", "mean": 5, "sd": 1e-3}})")),
                 "no probability inside bounds.c_q [0.02, 1]");
  // A prior's support must hold the start (here initial.c_q = 0.1), where the fit starts.
  expect_refused(write_file(dir, "p7.json", study_text(good, R"(, "priors": {"c_q": {"distribution": "uniform", "min": 0.5, "max": 0.6}})")),
                 "'priors.c_q'");
  expect_refused(write_file(dir, "p7.json", study_text(good, R"(, "priors": {"c_q": {"distribution": "uniform", "min": 0.5, "max": 0.6}})")),
                 "its support [0.5, 0.6] leaves out the start initial.c_q = 0.1");
  // Little probability inside the bounds is a proper truncated prior: accepted.
  EXPECT_EQ(load_calibration_study(write_file(dir, "p8.json", study_text(good, R"(, "priors": {"c_q": {"distribution": "normal", "mean": 1.5, "sd": 0.1}})")))
                .fit.at(0).prior.kind,
            DistributionKind::kNormal);
  // A noise prior reaching 0 m, below the noise sds the likelihood resolves.
  expect_refused(write_file(dir, "p9.json", study_text(good, R"(, "method": "mcmc", "mcmc": {"noise_sd": {"distribution": "uniform", "min": 0, "max": 1e-3}})")),
                 "the prior reaches 0 m");
  // A default start outside the bounds: blamed on the bounds, naming the default and initial.<name>.
  const std::string default_outside = R"({"type": "calibration", "name": "c", "scenario": ")" +
      rover::testing::source_path("configs/scenarios/drop_horizontal.json") + R"(", "data": ")" + good +
      R"(", "fit": ["c_q"], "bounds": {"c_q": [0.3, 1.0]}})";
  expect_refused(write_file(dir, "p10.json", default_outside), "'bounds.c_q'");
  expect_refused(write_file(dir, "p10.json", default_outside),
                 "the default start 0.14 (the nominal value of the rover and scenario files) is outside the bounds "
                 "[0.3, 1]: give a start inside them as initial.c_q");
  const CalibrationStudy k_g = load_calibration_study(write_file(dir, "p6.json", with_fit("contact.k_g", "[1e5, 1e7]", "2e6")));
  EXPECT_EQ(k_g.fit.at(0).canonical, "contact.k_g");
  EXPECT_TRUE(k_g.fit.at(0).log_scale);  // stiffnesses are searched in log10 by default
  // Joint fits: a list of curves, each with a known channel. The skewed rows
  // without their header, which declares B_l_z: a curve that declares none
  // may be fitted as any channel.
  std::string skewed_rows;
  {
    std::ifstream in(rover::testing::source_path("configs/data/drop_skewed_synthetic.csv"));
    for (std::string line; std::getline(in, line);)
      if (!line.starts_with("#")) skewed_rows += line + "\n";
  }
  const std::string skewed = write_file(dir, "skewed_rows.csv", skewed_rows);
  const std::string joint = R"(, "data": [{"file": ")" + good + R"("}, {"file": ")" + skewed +
                            R"(", "scenario": ")" + rover::testing::source_path("configs/scenarios/drop_skewed.json") +
                            R"(", "channel": "B_r_z"}])";
  std::string text = study_text(good);
  text = text.substr(0, text.find(R"(, "data")")) + joint + text.substr(text.find(R"(, "fit")"));
  const CalibrationStudy two = load_calibration_study(write_file(dir, "joint.json", text));
  ASSERT_EQ(two.datasets.size(), 2u);
  EXPECT_EQ(two.datasets[1].channel, "B_r_z");
  EXPECT_NE(two.datasets[1].model->nominal().scenario.initial_q, two.datasets[0].model->nominal().scenario.initial_q);
  std::string bad_channel = text;
  bad_channel.replace(bad_channel.find("B_r_z"), 5, "B_x_z");
  expect_refused(write_file(dir, "g.json", bad_channel), "'data[1].channel'");
  expect_refused(write_file(dir, "g.json", bad_channel), "unknown channel 'B_x_z' (valid: B_l_z, B_r_z, G_z)");
  std::string centre = text;
  centre.replace(centre.find("B_r_z"), 5, "G_z");
  EXPECT_EQ(load_calibration_study(write_file(dir, "g.json", centre)).datasets[1].channel, "G_z");
  std::string with_offset = text;
  with_offset.replace(with_offset.find(R"("fit": ["c_q"])"), 14, R"("fit": ["c_q", "time_offset"])");
  expect_refused(write_file(dir, "h.json", with_offset), "'fit'");
  const std::string no_file = text.substr(0, text.find(R"(, "data")")) + R"(, "data": [{"file": ")" + good +
                              R"("}, {"channel": "B_r_z"}])" + text.substr(text.find(R"(, "fit")"));
  expect_refused(write_file(dir, "i.json", no_file), "'data[1].file'");
  // A copy of a curve under another name is the same curve twice.
  const std::string copy = write_file(dir, "copy_of_skewed.csv", skewed_rows);
  std::string copied = text;
  copied.replace(copied.find("B_r_z"), 5, R"(B_r_z"}, {"file": ")" + copy + R"(", "scenario": ")" +
                                              rover::testing::source_path("configs/scenarios/drop_skewed.json") +
                                              R"(", "channel": "B_r_z)");
  expect_refused(write_file(dir, "j.json", copied), "'data[2].file'");
  expect_refused(write_file(dir, "j.json", copied), "holds the curve of data[1]");
  // A near copy (its first data row left out, every height moved by 1e-12 m)
  // is the same measurements too; a repeat that differs by 1e-5 m noise is not.
  const auto shifted_copy = [&](const std::string& name, double shift_m, int rows_left_out) {
    std::istringstream rows(skewed_rows);
    std::string out, line;
    std::getline(rows, line);
    out += line + "\n";  // the header
    for (int k = 0; std::getline(rows, line); ++k) {
      if (k < rows_left_out) continue;
      const std::size_t comma = line.find(',');
      const double z = std::stod(line.substr(comma + 1)) + (k % 2 == 0 ? shift_m : -shift_m);
      std::ostringstream row;
      row.precision(17);
      row << line.substr(0, comma) << "," << z;
      out += row.str() + "\n";
    }
    std::string study_text = copied;
    study_text.replace(study_text.find(copy), copy.size(), write_file(dir, name, out));
    return write_file(dir, "near_" + name + ".json", study_text);
  };
  expect_refused(shifted_copy("near_copy.csv", 1e-12, 1), "holds the curve of data[1]");
  // A copy rounded to micrometres (heights moved by up to half of one).
  expect_refused(shifted_copy("rounded_copy.csv", 4e-7, 0), "holds the curve of data[1]");
  EXPECT_EQ(load_calibration_study(shifted_copy("repeat.csv", 1e-5, 0)).datasets.size(), 3u);
  // The same numbers as another channel are another curve.
  std::string as_centre = copied;
  as_centre.replace(as_centre.rfind("B_r_z"), 5, "G_z");
  EXPECT_EQ(load_calibration_study(write_file(dir, "k.json", as_centre)).datasets.size(), 3u);

  // Every option that changes a result changes the fingerprint.
  EXPECT_NE(load_calibration_study(study, {.max_evaluations = 7}).fingerprint, s.fingerprint);
  EXPECT_NE(load_calibration_study(study, {.algorithm = "LN_SBPLX"}).fingerprint, s.fingerprint);
  const std::string other = write_file(dir, "other.csv", "t,z\n0,0.25\n0.1,0.24\n0.2,0.23\n");
  EXPECT_NE(load_calibration_study(study, {.data_path = other}).fingerprint, s.fingerprint);
  EXPECT_EQ(load_calibration_study(study).fingerprint, s.fingerprint);
}


// A posterior's target_ess above the draws its chains keep, walkers x (steps -
// burn-in), is never met: refused before any run, naming the bound, whether
// the target is the study's or the default one that short chains cannot meet.
TEST(Calibration, AnUnreachableTargetEssIsRefused) {
  const std::string dir = rover::testing::temp_dir();
  const std::string good = rover::testing::source_path("configs/data/drop_horizontal_synthetic.csv");
  auto mcmc = [&](const std::string& settings) {
    return write_file(dir, "mcmc.json", study_text(good, R"(, "method": "mcmc", "mcmc": )" + settings));
  };
  for (const std::string target : {"161", "1e9", "1e300"}) {
    SCOPED_TRACE(target);
    const std::string path = mcmc(R"({"walkers": 8, "steps": 30, "target_ess": )" + target + "}");
    expect_refused(path, "'mcmc.target_ess'");
    expect_refused(path, "8 x (30 - 10) = 160 draws");
    expect_refused(path, "from 0 (exactly 'steps' steps, no target) to 160");
  }
  EXPECT_EQ(load_calibration_study(mcmc(R"({"walkers": 8, "steps": 30, "target_ess": 160})")).mcmc.target_ess, 160);
  EXPECT_EQ(load_calibration_study(mcmc(R"({"walkers": 8, "steps": 30, "target_ess": 0})")).mcmc.target_ess, 0);
  // The default target 400, with chains the command line shortens.
  const std::string plain = write_file(dir, "plain.json", study_text(good, R"(, "method": "mcmc")"));
  expect_refused(plain, "--walkers 4 --steps 20: the default target_ess 400 can never be met",
                 {.walkers = 4, .steps = 20});
  // A burn-in given explicitly counts as given: 8 x (60 - 20) = 320.
  expect_refused(mcmc(R"({"walkers": 8, "steps": 60, "discard": 20, "target_ess": 400})"), "8 x (60 - 20) = 320");
}

}  // namespace
}  // namespace rover::study
