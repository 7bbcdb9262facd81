// The surrogate study in-process (no MPI): exact answers on test functions
// (a polynomial reproduced to 1e-10, the Ishigami indices within 0.01), a
// kriging model validated on held-out runs, training on a result file with
// failed runs, the round trip of a saved model, and the refusals.
#include "study/studies/surrogate_study.hpp"

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "io/hdf5_file.hpp"
#include "study/estimators/test_models.hpp"
#include "study/studies/surrogate_prediction.hpp"
#include "study/studies/surrogate_report.hpp"
#include "test_support.hpp"

namespace rover::study {
namespace {

SurrogateStudy load(const std::string& json, const std::string& dir = rover::testing::temp_dir()) {
  return load_surrogate_study(rover::testing::write_file(dir + "/surrogate.json", json));
}

// The study's design, every run made in this process.
TrainingRuns design_runs(const SurrogateStudy& s) {
  TrainingRuns runs;
  runs.source = "design";
  runs.x = study_design(s.spec);
  runs.y.resize(runs.x.rows(), static_cast<Eigen::Index>(s.qoi_names().size()));
  for (Eigen::Index i = 0; i < runs.x.rows(); ++i) {
    const RunRecord r = s.spec.model->run(runs.x.row(i).data());
    for (std::size_t q = 0; q < r.qoi.size(); ++q) runs.y(i, static_cast<Eigen::Index>(q)) = r.qoi[q];
    runs.status.push_back(r.status);
    runs.messages.push_back(r.message);
  }
  return runs;
}

SurrogateStudyResult fit_in_process(const SurrogateStudy& s) {
  TrainingRuns runs = design_runs(s);
  const int held = s.held_out_runs();
  return fit_surrogate_study(s, runs.slice(0, runs.runs() - held), runs.slice(runs.runs() - held, held));
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST(SurrogateStudy, LinearModelIsReproducedExactlyWithItsIndices) {
  // y = x1 + 2 x2 + 3 x3 + 4 x4, x_i ~ N(0, 1): S_i = i^2 / 30, mean 0, variance 30.
  const SurrogateStudy s = load(R"({"type": "surrogate", "name": "lin", "model": "linear",
      "design": {"samples": 40, "seed": 3}, "held_out": {"fraction": 0.25}, "pce": {"max_degree": 3, "bootstrap": 20}})");
  const SurrogateStudyResult r = fit_in_process(s);
  ASSERT_EQ(r.qoi.size(), 1u);
  const SurrogateQoiResult& q = r.qoi[0];
  ASSERT_TRUE(q.fitted && q.indices_defined) << q.undefined_reason;
  EXPECT_EQ(q.runs_used, 30);
  EXPECT_NEAR(q.model.validation().q2_loo, 1.0, 1e-10);
  EXPECT_EQ(q.model.validation().test_points, 10);
  EXPECT_NEAR(q.model.validation().rmse_test, 0.0, 1e-10);
  EXPECT_NEAR(q.indices.mean, 0.0, 1e-10);
  EXPECT_NEAR(q.indices.variance, 30.0, 1e-9);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(q.indices.S1(i), (i + 1) * (i + 1) / 30.0, 1e-10) << i;
    EXPECT_NEAR(q.indices.ST(i), (i + 1) * (i + 1) / 30.0, 1e-10) << i;
  }
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
}

TEST(SurrogateStudy, IshigamiIndicesWithinOneHundredthFrom500Runs) {
  const SurrogateStudy s = load(R"({"type": "surrogate", "name": "ish", "model": "ishigami",
      "design": {"type": "lhs", "samples": 500, "seed": 5}, "pce": {"max_degree": 14, "bootstrap": 50}})");
  const SurrogateStudyResult r = fit_in_process(s);
  const SurrogateQoiResult& q = r.qoi.at(0);
  ASSERT_TRUE(q.indices_defined) << q.undefined_reason;
  const KnownIndices exact = ishigami_indices();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(q.indices.S1(i), exact.S1(i), 0.01) << i;
    EXPECT_NEAR(q.indices.ST(i), exact.ST(i), 0.01) << i;
    EXPECT_LE(q.intervals.ST_lower(i), q.indices.ST(i));
    EXPECT_GE(q.intervals.ST_upper(i), q.indices.ST(i));
  }
  // The leave-one-out predictions are those of the corrected Q^2's error, before correction.
  const double sst = (q.actual.array() - q.actual.mean()).square().sum();
  const double q2_uncorrected = 1.0 - (q.actual - q.loo_predicted).squaredNorm() / sst;
  EXPECT_GE(q2_uncorrected, q.model.validation().q2_loo);
  EXPECT_GT(q.model.validation().q2_loo, 0.99);
}

TEST(SurrogateStudy, KrigingOfASmoothResponseIsValidatedOnHeldOutRuns) {
  const SurrogateStudy s = load(R"({"type": "surrogate", "surrogate": "gp", "name": "gp", "model": "linear",
      "parameters": {"x1": {"distribution": "uniform", "min": 0, "max": 1},
                     "x2": {"distribution": "log_uniform", "min": 1, "max": 100},
                     "x3": {"distribution": "uniform", "min": -1, "max": 1},
                     "x4": {"distribution": "uniform", "min": 0, "max": 2}},
      "design": {"samples": 50, "seed": 9}, "held_out": {"fraction": 0.2}, "gp": {"trend": "linear"}})");
  const SurrogateStudyResult r = fit_in_process(s);
  const SurrogateQoiResult& q = r.qoi.at(0);
  ASSERT_TRUE(q.fitted) << q.undefined_reason;
  EXPECT_FALSE(q.indices_defined);
  EXPECT_GT(q.model.validation().q2_loo, 0.99);
  EXPECT_EQ(q.model.validation().test_points, 10);
  EXPECT_GT(q.model.validation().q2_test, 0.99);
  // It interpolates its training runs, where its predictive sd vanishes.
  const TrainingRuns runs = design_runs(s).slice(0, 40);
  const SurrogatePrediction p = predict_surrogate(q.model, runs.x);
  EXPECT_LT((p.mean - runs.y.col(0)).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT(p.sd.maxCoeff(), 1e-2 * std::sqrt(q.model.gp.process_variance));
}

// A montecarlo-shaped result file of the Ishigami function: `failed` runs NaN
// with status 11, an extra input column `extra` (constant unless varied).
std::string ishigami_result_file(const std::string& dir, int runs, int failed, bool vary_extra = false) {
  const SurrogateStudy s = load(R"({"type": "surrogate", "name": "ish", "model": "ishigami",
      "design": {"type": "sobol", "samples": )" + std::to_string(runs) + R"(, "seed": 2}})", dir);
  const TrainingRuns r = design_runs(s);
  Eigen::MatrixXd values(r.x.rows(), 4);
  values.leftCols(3) = r.x;
  values.col(3).setConstant(1.5);
  if (vary_extra) values(0, 3) = 2.5;
  std::vector<double> y(r.y.data(), r.y.data() + r.y.size());
  std::vector<int> status(y.size(), 0);
  for (int i = 0; i < failed; ++i) {
    y[static_cast<std::size_t>(i)] = std::nan("");
    status[static_cast<std::size_t>(i)] = 11;
  }
  const std::string path = dir + "/mc.h5";
  io::Hdf5Writer h5(path);
  h5.write("/inputs/names", std::vector<std::string>{"x3", "x1", "x2", "extra"});
  Eigen::MatrixXd permuted(values.rows(), 4);
  permuted << values.col(2), values.col(0), values.col(1), values.col(3);
  h5.write("/inputs/values", permuted);
  h5.write("/qoi/y", y);
  h5.write("/samples/status", status);
  h5.commit();
  return path;
}

TEST(SurrogateStudy, TrainsOnAResultFileLeavingFailedRunsOut) {
  const std::string dir = rover::testing::temp_dir();
  const std::string file = ishigami_result_file(dir, 400, 7);
  const SurrogateStudy s = load(R"({"type": "surrogate", "name": "f", "model": "ishigami",
      "training": {"file": "mc.h5"}, "pce": {"max_degree": 14, "bootstrap": 0}})", dir);
  SurrogateStudy resized = s;
  EXPECT_THROW(set_surrogate_runs(resized, 100), std::invalid_argument);  // --samples sizes a design only
  const TrainingRuns runs = read_result_runs(s.training_file, s, "training");
  EXPECT_EQ(runs.runs(), 400);
  EXPECT_EQ(runs.failed_runs(), 7);
  const SurrogateStudyResult r = fit_surrogate_study(s, runs, TrainingRuns{});
  const SurrogateQoiResult& q = r.qoi.at(0);
  EXPECT_EQ(q.runs_used, 393);
  EXPECT_NEAR(q.indices.ST(0), ishigami_indices().ST(0), 0.02);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("7 of 400 training runs failed"), std::string::npos) << r.warnings[0];
}

TEST(SurrogateStudy, EveryDesignRunFailingGivesTheRunsAndNoModel) {
  const SurrogateStudy s = load(R"({"type": "surrogate", "name": "ish", "model": "ishigami",
      "design": {"samples": 20, "seed": 2}})");
  TrainingRuns runs = design_runs(s);
  for (int& status : runs.status) status = run_status::kError;
  runs.y.setConstant(std::nan(""));
  const SurrogateStudyResult r = fit_surrogate_study(s, runs, TrainingRuns{});
  EXPECT_EQ(r.training.failed_runs(), 20);
  ASSERT_EQ(r.qoi.size(), 1u);
  EXPECT_FALSE(r.qoi[0].fitted);
  EXPECT_NE(r.qoi[0].undefined_reason.find("every run failed"), std::string::npos) << r.qoi[0].undefined_reason;
  EXPECT_TRUE(r.set.models.empty());
}

TEST(SurrogateStudy, ResultFilesThatCannotTrainAreRefusedNamingFileAndField) {
  const std::string dir = rover::testing::temp_dir();
  const std::string head = R"({"type": "surrogate", "name": "f", "model": "ishigami", "training": {"file": "mc.h5"})";
  ishigami_result_file(dir, 40, 36);
  // Too few successful runs: refused as the study loads, naming the field.
  std::string m = message_of([&] { load(head + "}", dir); });
  EXPECT_NE(m.find("field 'training.file'"), std::string::npos) << m;
  EXPECT_NE(m.find("mc.h5: 4 successful training runs (36 failed)"), std::string::npos) << m;
  ishigami_result_file(dir, 40, 0);
  const SurrogateStudy few = load(head + "}", dir);
  ishigami_result_file(dir, 40, 0, /*vary_extra=*/true);
  m = message_of([&] { read_result_runs(few.training_file, few, "training"); });
  EXPECT_NE(m.find("input 'extra' varies"), std::string::npos) << m;
  {
    io::Hdf5Writer h5(dir + "/mc.h5");
    h5.write("/qoi/y", std::vector<double>{1.0, 2.0});
    h5.commit();
  }
  m = message_of([&] { read_result_runs(few.training_file, few, "training"); });
  EXPECT_NE(m.find("mc.h5: training runs: no /inputs/names and /inputs/values"), std::string::npos) << m;
  ishigami_result_file(dir, 40, 0);
  // The loader reads the training runs (to check that they cover each input's
  // support): a file that cannot train is refused as the study loads.
  m = message_of([&] {
    load(R"({"type": "surrogate", "name": "f", "scenario": ")" + rover::testing::short_drop_scenario(dir) + R"(",
        "parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.3}},
        "qoi": ["deflection"], "training": {"file": "mc.h5"}})", dir);
  });
  EXPECT_NE(m.find("field 'training.file'"), std::string::npos) << m;
  EXPECT_NE(m.find("no input 'c_q'"), std::string::npos) << m;
}

TEST(SurrogateStudy, UnknownQoiAndInputsOutsideTheirSupportAreRefused) {
  const std::string dir = rover::testing::temp_dir();
  ishigami_result_file(dir, 40, 0);
  {  // the same runs, renamed QoI
    const io::Hdf5Reader in(dir + "/mc.h5");
    io::Hdf5Writer h5(dir + "/other.h5");
    h5.write("/inputs/names", in.read_strings("/inputs/names"));
    h5.write("/inputs/values", in.read_matrix("/inputs/values"));
    h5.write("/qoi/z", in.read_doubles("/qoi/y"));
    h5.commit();
  }
  // The loader reads the training runs: a file that cannot train is refused as the study loads.
  std::string m = message_of([&] {
    load(R"({"type": "surrogate", "name": "f", "model": "ishigami", "training": {"file": "other.h5"}})", dir);
  });
  EXPECT_NE(m.find("field 'training.file'"), std::string::npos) << m;
  EXPECT_NE(m.find("other.h5: training runs: no QoI 'y' (/qoi holds: z)"), std::string::npos) << m;
  m = message_of([&] {
    load(R"({"type": "surrogate", "name": "f", "model": "ishigami",
        "parameters": {"x1": {"distribution": "uniform", "min": -1, "max": 1}}, "training": {"file": "mc.h5"}})", dir);
  });
  EXPECT_NE(m.find("x1 = "), std::string::npos) << m;
  EXPECT_NE(m.find("lies outside its distribution uniform"), std::string::npos) << m;
}

TEST(SurrogateStudy, BadStudyFilesAreRefusedNamingTheField) {
  const std::string head = R"({"type": "surrogate", "name": "s", "model": "ishigami", )";
  for (const auto& [json, field] : std::vector<std::pair<std::string, std::string>>{
           {head + R"("surrogate": "nn", "design": {"samples": 100}})", "surrogate"},
           {head + R"("design": {"samples": 100}, "pce": {"max_degree": 0}})", "pce.max_degree"},
           {head + R"("design": {"samples": 100}, "pce": {"max_degree": 50}})", "pce.max_degree"},
           {head + R"("design": {"samples": 100}, "pce": {"q_norm": 1.2}})", "pce.q_norm"},
           {head + R"("design": {"samples": 5}})", "design.samples"},
           {head + R"("design": {"samples": 8}, "held_out": {"fraction": 0.5}})", "design.samples"},
           {head + R"("design": {"samples": 100}, "held_out": {"fraction": 0.7}})", "held_out.fraction"},
           {head + R"("design": {"samples": 100}, "held_out": {"fraction": 0.01}})", "held_out.fraction"},
           {head + R"("design": {"samples": 100}, "held_out": {"file": "none.h5"}})", "held_out.file"},
           {head + R"("design": {"samples": 100}, "training": {"file": "none.h5"}})", "design"},
           {head + R"("training": {"file": "none.h5"}})", "training.file"},
           {head + R"("surrogate": "gp", "design": {"samples": 100}, "pce": {}})", "pce"},
           {head + R"("surrogate": "gp", "design": {"samples": 100}, "gp": {"trend": "quadratic"}})", "gp.trend"},
           {head + R"("surrogate": "gp", "design": {"samples": 100}, "gp": {"nugget": 1}})", "gp.nugget"},
           {head + R"("surrogate": "gp", "design": {"samples": 100}, "gp": {"nugget": "fit"}})", "gp.nugget"},
           {head + R"("surrogate": "gp", "design": {"samples": 100}, "compare": {"file": "none.h5"}})", "compare"},
           {head + R"("design": {"samples": 100}, "compare": {"file": "none.h5"}})", "compare.file"},
           {head + R"("design": {"samples": 100}, "parameters": {"x1": {"distribution": "fixed", "value": 0}}})",
            "parameters"},
       }) {
    const std::string m = message_of([&] { load(json); });
    EXPECT_NE(m.find("'" + field + "'"), std::string::npos) << json << "\n" << m;
    EXPECT_NE(m.find("surrogate.json"), std::string::npos) << m;
  }
  SurrogateStudy s = load(head + R"("design": {"samples": 100}})");
  EXPECT_THROW(set_surrogate_runs(s, min_training_runs(s) - 1), std::invalid_argument);
  set_surrogate_runs(s, min_training_runs(s));
  EXPECT_EQ(s.spec.design.samples, min_training_runs(s));
  // A held-out Q2 needs 2 runs: 0.1 of 100 holds out 10, of 10 only 1.
  SurrogateStudy held = load(head + R"("design": {"samples": 100}, "held_out": {"fraction": 0.1}})");
  const std::string m = message_of([&] { set_surrogate_runs(held, 10); });
  EXPECT_NE(m.find("--samples 10: 'held_out.fraction' 0.1 of 10 runs holds out 1 run"), std::string::npos) << m;
}

TEST(SurrogateStudy, ConstantQoiIsReportedWithoutIndices) {
  const std::string dir = rover::testing::temp_dir();
  {
    const SurrogateStudy s = load(R"({"type": "surrogate", "name": "i", "model": "ishigami",
        "design": {"samples": 30, "seed": 1}})", dir);
    const TrainingRuns r = design_runs(s);
    io::Hdf5Writer h5(dir + "/c.h5");
    h5.write("/inputs/names", std::vector<std::string>{"x1", "x2", "x3"});
    h5.write("/inputs/values", Eigen::MatrixXd(r.x));
    h5.write("/qoi/y", std::vector<double>(30, 2.5));
    h5.commit();
  }
  for (const char* kind : {"pce", "gp"}) {
    const SurrogateStudy s = load(std::string(R"({"type": "surrogate", "name": "c", "model": "ishigami",
        "surrogate": ")") + kind + R"(", "training": {"file": "c.h5"}})", dir);
    const SurrogateStudyResult r = fit_surrogate_study(s, read_result_runs(s.training_file, s, "training"), {});
    const SurrogateQoiResult& q = r.qoi.at(0);
    EXPECT_FALSE(q.indices_defined) << kind;
    EXPECT_NE(q.undefined_reason.find("constant"), std::string::npos) << q.undefined_reason;
    ASSERT_FALSE(r.warnings.empty()) << kind;
    EXPECT_NE(r.warnings.back().find("y:"), std::string::npos) << r.warnings.back();
    // The saved result names it at its root, as a sensitivity result does (a GP has no indices at all).
    const std::string saved = dir + "/" + kind + ".h5";
    {
      io::Hdf5Writer h5(saved);
      write_surrogate_study(h5, s, r);
      h5.commit();
    }
    const io::Hdf5Reader h5(saved);
    EXPECT_EQ(h5.has_attribute("/", "undefined_indices"), std::string(kind) == "pce") << kind;
    if (std::string(kind) == "pce") EXPECT_EQ(h5.attribute_string("/", "undefined_indices"), "y");
  }
}

// Saves the result as `rover surrogate` does and reads the set back.
SurrogateSet round_trip(const SurrogateStudy& s, const SurrogateStudyResult& r, const std::string& path) {
  io::Hdf5Writer h5(path);
  write_surrogate_study(h5, s, r);
  h5.commit();
  return read_surrogate_set(path);
}

TEST(SurrogateStudy, SavedModelsPredictWhatTheFittedOnesDo) {
  const std::string dir = rover::testing::temp_dir();
  for (const char* kind : {"pce", "gp"}) {
    const SurrogateStudy s = load(std::string(R"({"type": "surrogate", "name": "r", "model": "ishigami",
        "surrogate": ")") + kind + R"(", "design": {"samples": 120, "seed": 4}, "held_out": {"fraction": 0.1}})", dir);
    const SurrogateStudyResult r = fit_in_process(s);
    const SurrogateSet set = round_trip(s, r, dir + "/" + kind + ".h5");
    ASSERT_EQ(set.models.size(), 1u);
    EXPECT_EQ(set.kind, s.kind);
    const DesignMatrix x = map_to_distributions(unit_design(DesignType::kMonteCarlo, 25, 3, 77), s.distributions());
    const SurrogatePrediction fitted = predict_surrogate(r.set.models[0], x);
    const SurrogatePrediction saved = predict_surrogate(set.models[0], x);
    EXPECT_LT((fitted.mean - saved.mean).cwiseAbs().maxCoeff(), 1e-12 * fitted.mean.cwiseAbs().maxCoeff()) << kind;
    EXPECT_LT((fitted.sd - saved.sd).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + fitted.sd.maxCoeff())) << kind;
    EXPECT_EQ(set.models[0].validation().q2_loo, r.set.models[0].validation().q2_loo);
    EXPECT_EQ(set.models[0].validation().test_points, 12);
    const io::Hdf5Reader h5(dir + "/" + kind + ".h5");
    EXPECT_EQ(h5.read_matrix("/inputs/values").rows(), 108);
    EXPECT_EQ(h5.read_doubles("/held_out/qoi/y").size(), 12u);
  }
}

TEST(SurrogateStudy, PredictionRefusesPointsOutsideTheTrainingSupport) {
  const std::string dir = rover::testing::temp_dir();
  const SurrogateStudy s = load(R"({"type": "surrogate", "name": "p", "model": "linear",
      "parameters": {"x1": {"distribution": "uniform", "min": 0, "max": 1}},
      "design": {"samples": 30, "seed": 4}, "pce": {"max_degree": 2, "bootstrap": 0}})", dir);
  const SurrogateSet set = round_trip(s, fit_in_process(s), dir + "/p.h5");
  EXPECT_EQ(set.inputs[0].lower, 0.0);  // bounded: the distribution's support
  EXPECT_EQ(set.inputs[0].upper, 1.0);
  EXPECT_LT(set.inputs[1].upper, 5.0);  // normal: the training runs' range
  const auto design = [&](const std::string& text) {
    return read_design_csv(rover::testing::write_file(dir + "/x.csv", text));
  };
  const DesignMatrix x = surrogate_points(set, design("x4,x3,x2,x1\n0.1,0.2,0.3,0.5\n"));
  EXPECT_EQ(x(0, 0), 0.5);
  EXPECT_EQ(x(0, 3), 0.1);
  const PredictionTable t = predict_surrogate_set(set, x);
  ASSERT_EQ(t.header.back(), "y");
  EXPECT_NEAR(t.columns.back()[0], 0.5 + 2 * 0.3 + 3 * 0.2 + 4 * 0.1, 1e-10);
  std::string m = message_of([&] { surrogate_points(set, design("x1,x2,x3,x4\n0.5,0,0,0\n# far\n1.5,0,0,0\n")); });
  EXPECT_NE(m.find("x.csv:4: row 2: x1 = 1.5 lies outside the training support [0, 1]"), std::string::npos) << m;
  m = message_of([&] { surrogate_points(set, design("x1,x2,x3,x5\n0.5,0,0,0\n")); });
  EXPECT_NE(m.find("x.csv:1: column 4 'x5' is not an input of the surrogate"), std::string::npos) << m;
  m = message_of([&] { surrogate_points(set, design("x1,x2,x3\n0.5,0,0\n")); });
  EXPECT_NE(m.find("no column for input 'x4'"), std::string::npos) << m;
}

// A lognormal's support starts at 0, but the runs never come near it: the
// prediction support is the training runs' range, as for a normal.
TEST(SurrogateStudy, HalfBoundedInputsArePredictedOnlyWhereTheyWereTrained) {
  const std::string dir = rover::testing::temp_dir();
  const SurrogateStudy s = load(R"({"type": "surrogate", "name": "p", "model": "linear",
      "parameters": {"x1": {"distribution": "lognormal", "mean": 1, "sd": 0.2},
                     "x2": {"distribution": "normal", "mean": 1, "sd": 0.1, "truncate": [0, null]}},
      "design": {"samples": 30, "seed": 4}, "pce": {"max_degree": 1, "bootstrap": 0}})", dir);
  const SurrogateStudyResult r = fit_in_process(s);
  const SurrogateSet set = round_trip(s, r, dir + "/p.h5");
  for (Eigen::Index j = 0; j < 2; ++j) {
    EXPECT_EQ(set.inputs[static_cast<std::size_t>(j)].lower, r.training.x.col(j).minCoeff()) << j;
    EXPECT_EQ(set.inputs[static_cast<std::size_t>(j)].upper, r.training.x.col(j).maxCoeff()) << j;
  }
  EXPECT_GT(set.inputs[0].lower, 0.4);  // 3 sd above the lognormal's end
  const std::string m = message_of([&] {
    surrogate_points(set, read_design_csv(rover::testing::write_file(dir + "/x.csv", "x1,x2,x3,x4\n1e-6,1,0,0\n")));
  });
  EXPECT_NE(m.find("x1 = 1e-06 lies outside the training support"), std::string::npos) << m;
}

}  // namespace
}  // namespace rover::study
