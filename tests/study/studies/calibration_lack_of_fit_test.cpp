// The judgement of residuals at a calibration's answer
// (study/studies/calibration_lack_of_fit.hpp) against the chi-square law of
// independent Gaussian noise: residuals of the stated noise are never said
// to contradict it, residuals a third larger, or a third as large, always are.
#include "study/studies/calibration_lack_of_fit.hpp"

#include <cmath>
#include <vector>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/normal_distribution.hpp>
#include <gtest/gtest.h>

namespace rover::study {
namespace {

CalibrationStudy study_of_curves(std::size_t curves, std::size_t points) {
  CalibrationStudy s;
  for (std::size_t k = 0; k < curves; ++k) {
    CalibrationDataset d;
    d.path = "curve" + std::to_string(k) + ".csv";
    d.t.assign(points, 0.0);
    d.z.assign(points, 0.0);
    s.datasets.push_back(d);
  }
  return s;
}

// The residual sum of squares of `points` Gaussian residuals of sd `sd_m`.
double gaussian_rss(boost::random::mt19937_64& engine, std::size_t points, double sd_m) {
  boost::random::normal_distribution<double> noise(0.0, sd_m);
  double rss = 0.0;
  for (std::size_t i = 0; i < points; ++i) rss += std::pow(noise(engine), 2);
  return rss;
}

TEST(CalibrationLackOfFit, ResidualsOfTheStatedNoiseNeverContradictIt) {
  constexpr double kNoiseSd_m = 1e-4;
  boost::random::mt19937_64 engine(5);
  for (const std::size_t points : {3u, 20u, 500u, 5000u}) {
    const CalibrationStudy s = study_of_curves(2, points);
    for (int replicate = 0; replicate < 500; ++replicate) {
      const std::vector<double> rss{gaussian_rss(engine, points, kNoiseSd_m), gaussian_rss(engine, points, kNoiseSd_m)};
      EXPECT_EQ(noise_contradiction_reason(s, rss, kNoiseSd_m), "") << points;
    }
  }
}

TEST(CalibrationLackOfFit, ResidualsFarAboveTheStatedNoiseContradictItAndNameTheCurve) {
  constexpr double kNoiseSd_m = 1e-4;
  boost::random::mt19937_64 engine(6);
  const CalibrationStudy s = study_of_curves(2, 500);
  for (int replicate = 0; replicate < 100; ++replicate) {
    const std::vector<double> rss{gaussian_rss(engine, 500, kNoiseSd_m), gaussian_rss(engine, 500, 1.4 * kNoiseSd_m)};
    const std::string why = noise_contradiction_reason(s, rss, kNoiseSd_m);
    EXPECT_NE(why.find("curve1.csv"), std::string::npos) << why;
    EXPECT_EQ(why.find("curve0.csv"), std::string::npos) << why;
  }
  // A failed curve (NaN) and a sampled noise (sd 0) say nothing.
  EXPECT_EQ(noise_contradiction_reason(s, {gaussian_rss(engine, 500, kNoiseSd_m), std::nan("")}, kNoiseSd_m), "");
  EXPECT_EQ(noise_contradiction_reason(s, {1.0, 1.0}, 0.0), "");
}

// A stated noise sd far above the residuals' scatter makes the posterior too
// wide: residuals at a third of it (chi-square about n / 9, more than 5 sd of
// its lower tail below n for 100 points and more) are named, with the value
// and the residual RMS; those at the stated noise are not.
TEST(CalibrationLackOfFit, ResidualsFarBelowTheStatedNoiseContradictItAndNameTheCurve) {
  constexpr double kNoiseSd_m = 1e-4;
  boost::random::mt19937_64 engine(7);
  for (const std::size_t points : {100u, 500u, 5000u}) {
    const CalibrationStudy s = study_of_curves(2, points);
    for (int replicate = 0; replicate < 100; ++replicate) {
      const std::vector<double> rss{gaussian_rss(engine, points, kNoiseSd_m / 3.0),
                                    gaussian_rss(engine, points, kNoiseSd_m)};
      const std::string why = noise_contradiction_reason(s, rss, kNoiseSd_m);
      EXPECT_NE(why.find("contradict mcmc.noise_sd 0.0001 m from below (curve0.csv: residual RMS "), std::string::npos)
          << why;
      EXPECT_NE(why.find("too wide"), std::string::npos) << why;
      EXPECT_EQ(why.find("curve1.csv"), std::string::npos) << why;
    }
  }
  // A noise sd 100 times the residual RMS, over 20 points: named with both.
  const CalibrationStudy twenty = study_of_curves(1, 20);
  const std::string why = noise_contradiction_reason(twenty, {20 * 1e-8}, 1e-2);
  EXPECT_NE(why.find("mcmc.noise_sd 0.01 m from below (curve0.csv: residual RMS 0.0001 m, 0.01 times the noise sd"),
            std::string::npos) << why;
}

TEST(CalibrationLackOfFit, CorrelatedResidualsAreNamedAndWhiteOnesAreNot) {
  const CalibrationStudy s = study_of_curves(2, 400);
  EXPECT_EQ(residual_structure_reason(s, {0.02, -0.1}), "");
  const std::string why = residual_structure_reason(s, {0.9, std::nan("")});
  EXPECT_NE(why.find("curve0.csv: lag-1 autocorrelation 0.9"), std::string::npos) << why;
  EXPECT_EQ(why.find("curve1.csv"), std::string::npos) << why;
}

}  // namespace
}  // namespace rover::study
