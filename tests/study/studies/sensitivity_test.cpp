// The sensitivity study's whole path (study file -> design -> model runs ->
// indices) on analytic models with known indices, in-process.
#include "study/studies/sensitivity.hpp"

#include <algorithm>
#include <fstream>
#include <memory>

#include <gtest/gtest.h>

#include "study/estimators/test_models.hpp"
#include "study/studies/constant_qoi_model.hpp"
#include "test_support.hpp"

namespace rover::study {
namespace {

SensitivityStudy load(const std::string& json) {
  const std::string path = rover::testing::temp_dir() + "/s.json";
  std::ofstream(path) << json;
  return load_sensitivity_study(path);
}

SensitivityResult run_in_process(const SensitivityStudy& s) {
  const DesignMatrix x = sensitivity_design(s);
  std::vector<RunRecord> records;
  for (Eigen::Index i = 0; i < x.rows(); ++i) records.push_back(s.spec.model->run(x.row(i).data()));
  return analyse_sensitivity(s, x, records);
}

TEST(Sensitivity, IshigamiIndicesThroughTheStudyPath) {
  const SensitivityStudy s = load(R"({"type": "sensitivity", "method": "sobol", "name": "i", "model": "ishigami",
                                      "design": {"type": "sobol", "samples": 4096, "seed": 3}, "bootstrap": 300})");
  EXPECT_EQ(s.spec.design.samples, 4096 * 5);
  const SensitivityResult r = run_in_process(s);
  const KnownIndices exact = ishigami_indices();
  const SobolIndices& est = r.sobol.at(0);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(est.S1[i], exact.S1[i], 0.02) << i;
    EXPECT_NEAR(est.ST[i], exact.ST[i], 0.02) << i;
    EXPECT_LE(est.ST_lower[i], exact.ST[i]) << i;
    EXPECT_GE(est.ST_upper[i], exact.ST[i]) << i;
  }
  EXPECT_EQ(r.failed_runs, 0);
}

TEST(Sensitivity, MorrisRanksTheGFunctionByItsCoefficients) {
  const SensitivityStudy s = load(R"({"type": "sensitivity", "method": "morris", "name": "g", "model": "sobol_g",
                                      "design": {"trajectories": 40, "levels": 4, "seed": 2}, "bootstrap": 200})");
  const SensitivityResult r = run_in_process(s);
  const std::vector<int>& rank = r.morris.at(0).ranking;
  EXPECT_EQ(rank[0], 0);  // a = 0: the most important
  EXPECT_EQ(rank[1], 1);  // a = 1
  EXPECT_EQ(rank[2], 2);  // a = 4.5
  EXPECT_EQ(rank[3], 3);  // a = 9
}

TEST(Sensitivity, AConstantQoiHasUndefinedIndicesAndTheOthersAreKept) {
  for (const std::string method : {"sobol", "morris"}) {
    const std::string design = method == "sobol" ? R"({"type": "sobol", "samples": 256, "seed": 3})"
                                                 : R"({"trajectories": 20, "levels": 4, "seed": 2})";
    SensitivityStudy s = load(R"({"type": "sensitivity", "method": ")" + method +
                              R"(", "name": "i", "model": "ishigami", "design": )" + design + R"(, "bootstrap": 200})");
    s.spec.model = std::make_shared<ConstantQoiModel>(3);
    const SensitivityResult r = run_in_process(s);
    const auto c = std::find_if(r.undefined.begin(), r.undefined.end(),
                                [](const UndefinedIndices& u) { return u.qoi == "c"; });
    ASSERT_NE(c, r.undefined.end()) << method;
    EXPECT_NE(c->reason.find("constant"), std::string::npos) << c->reason;
    EXPECT_TRUE(std::none_of(r.undefined.begin(), r.undefined.end(),
                             [](const UndefinedIndices& u) { return u.qoi == "y"; }));
    EXPECT_TRUE(std::any_of(r.warnings.begin(), r.warnings.end(),
                            [](const std::string& w) { return w.starts_with("c: indices undefined"); }));
    if (method == "sobol") {
      ASSERT_EQ(r.sobol.size(), 3u);
      EXPECT_EQ(r.sobol[1].S1.size(), 0);
      EXPECT_GT(r.sobol[0].ST[1], r.sobol[0].ST[0]);  // on (-pi, pi), 2 x2^2 varies ten times more than x1
      EXPECT_NEAR(r.sobol[0].ST[2], 0.0, 1e-12);      // x3 does not enter y
    } else {
      ASSERT_EQ(r.morris.size(), 3u);
      EXPECT_EQ(r.morris[1].mu_star.size(), 0);
      EXPECT_EQ(r.morris[0].ranking[0], 1);
    }
  }
}

TEST(Sensitivity, BadStudiesNameTheField) {
  for (const auto& [json, field] : std::vector<std::pair<std::string, std::string>>{
           {R"({"type": "sensitivity", "method": "sobl", "name": "i", "model": "ishigami", "design": {"samples": 8}})", "method"},
           {R"({"type": "sensitivity", "method": "sobol", "name": "i", "model": "ishigami", "design": {"samples": 1}})", "design.samples"},
           {R"({"type": "sensitivity", "method": "sobol", "name": "i", "model": "ishigami", "design": {"samples": 8}, "bootstrap": 5})", "bootstrap"},
           {R"({"type": "sensitivity", "method": "morris", "name": "i", "model": "ishigami", "design": {"trajectories": 4, "levels": 3}})", "design.levels"},
           {R"({"type": "sensitivity", "method": "sobol", "name": "i", "model": "ishigam", "design": {"samples": 8}})", "model"},
       }) {
    try {
      load(json);
      ADD_FAILURE() << json;
    } catch (const io::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("'" + field + "'"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace rover::study
