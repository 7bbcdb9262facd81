// The Monte Carlo analysis in-process (no MPI, no files): on an analytic model
// with a known output distribution, the summaries' intervals contain the truth.
#include "study/studies/montecarlo.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace rover::study {
namespace {

StudySpec analytic_spec(const std::string& json_text) {
  const io::Json json = io::Json::parse(json_text);
  const io::JsonReader r(json, "inline.json");
  StudySpec spec = parse_study_spec(r, {"montecarlo"});
  r.finish();
  return spec;
}

MonteCarloResult analyse(const StudySpec& spec) {
  const DesignMatrix x = study_design(spec);
  MonteCarloAnalysis analysis(spec.model->layout(), spec.design.samples, 0.95, 500, 3);
  for (Eigen::Index i = 0; i < x.rows(); ++i) analysis.add(spec.model->run(x.row(i).data()));
  return analysis.finish();
}

TEST(MonteCarlo, LinearModelMomentsLieInTheirIntervals) {
  // y = x1 + 2 x2 + 3 x3 + 4 x4, x_i ~ N(0, 1): y ~ N(0, 30).
  const StudySpec spec = analytic_spec(
      R"({"type": "montecarlo", "name": "lin", "model": "linear",
          "design": {"type": "latin_hypercube", "samples": 4000, "seed": 11}})");
  const MonteCarloResult r = analyse(spec);
  ASSERT_EQ(r.summaries.size(), 1u);
  const QoiSummary& s = r.summaries[0];
  EXPECT_EQ(s.samples, 4000);
  EXPECT_LE(s.mean_lower, 0.0);
  EXPECT_GE(s.mean_upper, 0.0);
  EXPECT_LE(s.sd_lower, std::sqrt(30.0));
  EXPECT_GE(s.sd_upper, std::sqrt(30.0));
  EXPECT_LT(s.sd_upper - s.sd_lower, 0.5);
  // The median's distribution-free interval contains 0; the 0.135 % quantile's
  // exists at N = 4000 and contains -3 sd.
  ASSERT_EQ(s.quantiles.size(), 3u);
  EXPECT_LE(s.quantiles[1].lower, 0.0);
  EXPECT_GE(s.quantiles[1].upper, 0.0);
  EXPECT_TRUE(s.quantiles[0].interval_exists);
  EXPECT_LE(s.quantiles[0].lower, -3.0 * std::sqrt(30.0));
  EXPECT_GE(s.quantiles[0].upper, -3.0 * std::sqrt(30.0));
}

TEST(MonteCarlo, SmallSamplesSayTheTailQuantilesMeanNothing) {
  const StudySpec spec = analytic_spec(
      R"({"type": "montecarlo", "name": "ishi", "model": "ishigami",
          "design": {"type": "monte_carlo", "samples": 200, "seed": 1}})");
  const MonteCarloResult r = analyse(spec);
  const QoiSummary& s = r.summaries[0];
  EXPECT_FALSE(s.quantiles[0].interval_exists);
  EXPECT_FALSE(s.quantiles[2].interval_exists);
  EXPECT_TRUE(s.quantiles[1].interval_exists);
  EXPECT_NE(s.note.find("0.135"), std::string::npos) << s.note;
  // Ishigami, a = 7, b = 0.1: E[y] = a / 2 = 3.5.
  EXPECT_LE(s.mean_lower, 3.5);
  EXPECT_GE(s.mean_upper, 3.5);
}

TEST(MonteCarlo, FailedRunsAreCountedAndLeftOut) {
  MonteCarloAnalysis a({1, 1, 3}, 3);
  RunRecord ok;
  ok.qoi = {1.0};
  ok.curves = {1.0, 2.0, 3.0};
  a.add(ok);
  a.add(failed_record({1, 1, 3}, 2, "step size underflow"));
  ok.qoi = {3.0};
  ok.curves = {3.0, 4.0, 5.0};
  a.add(ok);
  const MonteCarloResult r = a.finish();
  EXPECT_EQ(r.failed, 1);
  EXPECT_EQ(r.summaries[0].samples, 2);
  EXPECT_EQ(r.summaries[0].mean, 2.0);
  EXPECT_EQ(r.bands[0].samples_used, 2);
  EXPECT_EQ(r.bands[0].mean, (std::vector<double>{2.0, 3.0, 4.0}));
  EXPECT_EQ(r.status, (std::vector<int>{0, 2, 0}));
  EXPECT_EQ(r.messages[1], "step size underflow");
}

}  // namespace
}  // namespace rover::study
