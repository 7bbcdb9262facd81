// The sensitivity study with "method": "pce" (sparse polynomial chaos,
// Blatman & Sudret 2011; indices from the coefficients, Sudret 2008): the
// Ishigami indices through the study path, the settings it refuses, and a
// constant or NaN QoI reported undefined while the others get their indices.
#include "study/studies/pce_sensitivity.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "io/hdf5_file.hpp"
#include "study/estimators/test_models.hpp"
#include "study/studies/sensitivity.hpp"
#include "study/studies/constant_qoi_model.hpp"
#include "test_support.hpp"

namespace rover::study {
namespace {

SensitivityStudy load(const std::string& json) {
  const std::string path = rover::testing::temp_dir() + "/pce.json";
  std::ofstream(path) << json;
  return load_sensitivity_study(path);
}

SensitivityResult run_in_process(const SensitivityStudy& s) {
  const DesignMatrix x = sensitivity_design(s);
  std::vector<RunRecord> records;
  for (Eigen::Index i = 0; i < x.rows(); ++i) records.push_back(s.spec.model->run(x.row(i).data()));
  return analyse_sensitivity(s, x, records);
}

TEST(PceSensitivity, IshigamiIndicesFrom500LhsRuns) {
  const SensitivityStudy s = load(R"({"type": "sensitivity", "method": "pce", "name": "i", "model": "ishigami",
      "design": {"type": "lhs", "samples": 500, "seed": 7}, "pce": {"max_degree": 14, "bootstrap": 100}})");
  ASSERT_EQ(s.method, SensitivityMethod::kPce);
  EXPECT_EQ(sensitivity_design(s).rows(), 500);
  const SensitivityResult r = run_in_process(s);
  const KnownIndices exact = ishigami_indices();
  ASSERT_EQ(r.pce.qoi.size(), 1u);
  const PceQoiResult& q = r.pce.qoi[0];
  ASSERT_TRUE(q.indices.defined) << q.undefined_reason;
  EXPECT_GT(q.expansion.validation.q2_loo, 0.99);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(q.indices.S1[i], exact.S1[i], 0.01) << i;
    EXPECT_NEAR(q.indices.ST[i], exact.ST[i], 0.01) << i;
    ASSERT_TRUE(q.has_intervals);
    EXPECT_LE(q.intervals.ST_lower[i], q.indices.ST[i] + 1e-12) << i;
    EXPECT_GE(q.intervals.ST_upper[i], q.indices.ST[i] - 1e-12) << i;
  }
}

TEST(PceSensitivity, BadSettingsAreRefusedNamingTheField) {
  const std::string head = R"({"type": "sensitivity", "method": "pce", "name": "i", "model": "ishigami", )";
  for (const auto& [json, field] : std::vector<std::pair<std::string, std::string>>{
           {head + R"("design": {"samples": 100}, "pce": {"max_degree": 0}})", "pce.max_degree"},
           {head + R"("design": {"samples": 100}, "pce": {"max_degree": 21}})", "pce.max_degree"},
           {head + R"("design": {"samples": 100}, "pce": {"q_norm": 0}})", "pce.q_norm"},
           {head + R"("design": {"samples": 100}, "pce": {"q_norm": 1.5}})", "pce.q_norm"},
           {head + R"("design": {"samples": 100}, "pce": {"bootstrap": -1}})", "pce.bootstrap"},
           {head + R"("design": {"samples": 100}, "pce": {"degree": 3}})", "pce.degree"},
           {head + R"("design": {"samples": 3}})", "design.samples"},
           {head + R"("design": {"type": "grid", "samples": 100}})", "design.type"},
           {head + R"("design": {"samples": 100}, "bootstrap": 100})", "bootstrap"},
       }) {
    try {
      load(json);
      ADD_FAILURE() << json;
    } catch (const io::ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("'" + field + "'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("pce.json"), std::string::npos) << e.what();
    }
  }
}

TEST(PceSensitivity, TooFewRunsForTheCommandLineAreRefused) {
  const std::string path = rover::testing::temp_dir() + "/pce.json";
  std::ofstream(path) << R"({"type": "sensitivity", "method": "pce", "name": "i", "model": "ishigami",
      "design": {"samples": 100}})";
  const SensitivityStudy s = load_sensitivity_study(path);
  const long long too_few = min_pce_sensitivity_runs(s.spec, s.pce) - 1;
  EXPECT_THROW(load_sensitivity_study(path, {too_few, std::nullopt}), std::invalid_argument);
  EXPECT_EQ(sensitivity_design(load_sensitivity_study(path, {50, std::nullopt})).rows(), 50);
}

TEST(PceSensitivity, TheCommandLineSizeReplacesATooSmallFileSize) {
  const std::string path = rover::testing::temp_dir() + "/pce.json";
  std::ofstream(path) << R"({"type": "sensitivity", "method": "pce", "name": "i", "model": "ishigami",
      "design": {"samples": 2}})";
  EXPECT_THROW(load_sensitivity_study(path), io::ConfigError);
  EXPECT_EQ(sensitivity_design(load_sensitivity_study(path, {50, std::nullopt})).rows(), 50);
}

TEST(PceSensitivity, ALowQ2WarnsNamingTheQoiAndALargerN) {
  // A cubic cannot follow sin(x1) + 7 sin^2(x2) on [-pi, pi]: Q2 stays well below 0.95.
  const SensitivityStudy s = load(R"({"type": "sensitivity", "method": "pce", "name": "i", "model": "ishigami",
      "design": {"type": "lhs", "samples": 40, "seed": 3}, "pce": {"max_degree": 3, "bootstrap": 0}})");
  const SensitivityResult r = run_in_process(s);
  const PceQoiResult& q = r.pce.qoi.at(0);
  ASSERT_TRUE(q.indices.defined);
  EXPECT_LT(q.expansion.validation.q2_loo, 0.95);
  EXPECT_FALSE(q.has_intervals);
  bool warned = false;
  for (const std::string& w : r.warnings)
    warned = warned || (w.find("'y'") != std::string::npos && w.find("from 40 runs") != std::string::npos &&
                        w.find("larger N") != std::string::npos);
  EXPECT_TRUE(warned);
}

// Ishigami from 30 runs at degree 1: no term beyond the constant explains
// it (sin x1 is the only odd effect, and weak at this size). The QoI varies:
// its indices are undefined for that reason, never called constant.
TEST(PceSensitivity, AnExpansionOfTheConstantAloneIsNotAConstantQoi) {
  const SensitivityStudy s = load(R"({"type": "sensitivity", "method": "pce", "name": "i", "model": "ishigami",
      "design": {"type": "lhs", "samples": 30, "seed": 3}, "pce": {"max_degree": 1, "bootstrap": 100}})");
  const SensitivityResult r = run_in_process(s);
  const PceQoiResult& q = r.pce.qoi.at(0);
  EXPECT_FALSE(q.indices.defined);
  EXPECT_NE(q.undefined_reason.find("varies over the 30 runs"), std::string::npos) << q.undefined_reason;
  EXPECT_NE(q.undefined_reason.find("selected no term beyond the constant"), std::string::npos) << q.undefined_reason;
  EXPECT_EQ(q.undefined_reason.find("constant over"), std::string::npos) << q.undefined_reason;
}

// Ishigami from 20 runs at degree 3: the selection leaves x2 out (its true
// S1 is 0.44), so its indices are 0 whatever the coefficients. The bootstrap
// cannot show that uncertainty: the result marks them and warns.
TEST(PceSensitivity, IndicesTheSelectionFixesAreMarkedAndWarnedOf) {
  const SensitivityStudy s = load(R"({"type": "sensitivity", "method": "pce", "name": "i", "model": "ishigami",
      "design": {"type": "lhs", "samples": 20, "seed": 3}, "pce": {"max_degree": 3, "bootstrap": 100}})");
  SensitivityResult r = run_in_process(s);
  r.study = s;  // as run_sensitivity() sets it, for the report
  const PceQoiResult& q = r.pce.qoi.at(0);
  ASSERT_TRUE(q.has_intervals);
  ASSERT_TRUE(q.intervals.fixed_by_selection.ST[1]) << "x2 was selected: the case no longer shows a fixed index";
  EXPECT_EQ(q.intervals.ST_lower(1), q.intervals.ST_upper(1));
  bool warned = false;
  for (const std::string& w : r.warnings)
    warned = warned || (w.find("the selected terms fix S1 x2, ST x2 at 0 or 1") != std::string::npos &&
                        w.find("Q2_LOO") != std::string::npos);
  EXPECT_TRUE(warned);
  std::ostringstream report;
  report_sensitivity(r, report);
  EXPECT_NE(report.str().find(std::string("ST  0.000 ") + kFixedBySelectionText), std::string::npos) << report.str();
}

TEST(PceSensitivity, ConstantAndNanQoisAreUndefinedWhileTheOthersAreWritten) {
  StudySpec spec;
  spec.name = "constant";
  spec.model = std::make_shared<ConstantQoiModel>();
  spec.inputs = {{"x1", "x1", uniform(-1.0, 1.0), 0.0}, {"x2", "x2", uniform(-1.0, 1.0), 0.0}};
  PceSensitivityOptions options;
  options.settings.max_degree = 4;
  options.bootstrap = 50;
  const DesignMatrix x = map_to_distributions(unit_design(DesignType::kLatinHypercube, 60, 2, 5),
                                              {uniform(-1.0, 1.0), uniform(-1.0, 1.0)});
  std::vector<RunRecord> records;
  for (Eigen::Index i = 0; i < x.rows(); ++i) records.push_back(spec.model->run(x.row(i).data()));
  records[3].status = run_status::kError;  // one failed run: left out
  const PceSensitivityResult r = analyse_pce_sensitivity(spec, options, x, records);
  EXPECT_EQ(r.runs_used, 59);
  ASSERT_EQ(r.qoi.size(), 3u);
  // y: V(x1) = 1/3, V(2 x2^2) = 4 (1/5 - 1/9) = 16/45.
  ASSERT_TRUE(r.qoi[0].indices.defined);
  EXPECT_NEAR(r.qoi[0].indices.S1[0], (1.0 / 3) / (1.0 / 3 + 16.0 / 45), 1e-6);
  EXPECT_FALSE(r.qoi[1].indices.defined);
  EXPECT_NE(r.qoi[1].undefined_reason.find("constant"), std::string::npos) << r.qoi[1].undefined_reason;
  EXPECT_FALSE(r.qoi[2].indices.defined);
  EXPECT_NE(r.qoi[2].undefined_reason.find("non-finite"), std::string::npos) << r.qoi[2].undefined_reason;

  std::ostringstream report;
  print_pce_sensitivity(report, spec, options, r);
  EXPECT_NE(report.str().find("c: indices undefined"), std::string::npos) << report.str();
  EXPECT_NE(report.str().find("y (PCE degree"), std::string::npos) << report.str();
  EXPECT_EQ(report.str().find("nan"), std::string::npos) << report.str();

  const std::string path = rover::testing::temp_dir() + "/constant.h5";
  {
    io::Hdf5Writer h5(path);
    write_pce_sensitivity(h5, spec, options, r);
    h5.commit();
  }
  const io::Hdf5Reader h5(path);
  EXPECT_EQ(h5.read_doubles("/indices/y/S1").size(), 2u);
  EXPECT_TRUE(h5.exists("/pce/y/coefficients"));
  EXPECT_EQ(h5.attribute_integer("/indices/y", "defined"), 1);
  for (const std::string q : {"c", "n"}) {
    EXPECT_FALSE(h5.exists("/indices/" + q + "/S1")) << q;
    EXPECT_EQ(h5.attribute_integer("/indices/" + q, "defined"), 0) << q;
    EXPECT_FALSE(h5.attribute_string("/indices/" + q, "undefined_reason").empty()) << q;
  }
  EXPECT_EQ(h5.read_doubles("/indices/c/variance"), std::vector<double>{0.0});
  EXPECT_EQ(h5.read_doubles("/indices/c/mean"), std::vector<double>{3.0});
  EXPECT_FALSE(h5.exists("/indices/n/mean"));
}

}  // namespace
}  // namespace rover::study
