// Study files: parameters by name, the preload group from the rover file,
// relative sds, grids, and errors that name the field.
#include "study/studies/study_spec.hpp"

#include <gtest/gtest.h>

namespace rover::study {
namespace {

const std::string kScenario = ROVER_SOURCE_DIR "/configs/scenarios/drop_horizontal.json";

StudySpec parse(const std::string& body) {
  const io::Json json = io::Json::parse(R"({"type": "montecarlo", "name": "t", "scenario": ")" + kScenario +
                                        "\", " + body + "}");
  const io::JsonReader r(json, "inline.json");
  StudySpec spec = parse_study_spec(r, {"montecarlo"});
  r.finish();
  return spec;
}

std::string error_of(const std::string& body) {
  try {
    parse(body);
  } catch (const io::ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(StudySpec, PreloadGroupExpandsFromTheRoverFile) {
  const StudySpec s = parse(R"("parameters": {"M0": {"distribution": "normal", "from_config": true, "sd_scale": 2}},
                               "design": {"type": "monte_carlo", "samples": 4}, "qoi": ["t_min"])");
  ASSERT_EQ(s.inputs.size(), 8u);
  EXPECT_EQ(s.inputs[0].label, "M0_11");
  EXPECT_EQ(s.inputs[7].name, "s_structure.preload_mean[7]");
  EXPECT_DOUBLE_EQ(s.inputs[7].distribution.mean(), 1.117);
  EXPECT_DOUBLE_EQ(s.inputs[7].distribution.sd(), 2 * 0.032);
}

TEST(StudySpec, RelativeSdAndGridLevels) {
  const StudySpec s = parse(R"("parameters": {"contact.k_g": {"distribution": "normal", "sd_percent": 10},
                                              "c_q": {"distribution": "uniform", "min": 0.1, "max": 0.3},
                                              "f": {"distribution": "log_uniform", "min": 1e2, "max": 1e4}},
                               "design": {"type": "grid", "levels": {"c_q": 3, "f": 3, "contact.k_g": 1}},
                               "qoi": ["t_min"])");
  EXPECT_DOUBLE_EQ(s.inputs[0].distribution.sd(), 1e5);
  // A normal input cannot be gridded (unbounded).
  EXPECT_NE(error_of(R"("parameters": {"contact.k_g": {"distribution": "normal", "sd_percent": 10}},
                        "design": {"type": "grid", "levels": 3}, "qoi": ["t_min"])").find("bounded"), std::string::npos);
  const StudySpec g = parse(R"("parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.3},
                                              "f": {"distribution": "log_uniform", "min": 1e2, "max": 1e4}},
                               "design": {"type": "grid", "levels": {"c_q": 3, "f": 3}}, "qoi": ["t_min"])");
  const DesignMatrix x = study_design(g);
  ASSERT_EQ(x.rows(), 9);
  EXPECT_DOUBLE_EQ(x(0, 0), 0.1);
  EXPECT_DOUBLE_EQ(x(8, 0), 0.3);
  EXPECT_NEAR(x(1, 1), 1e3, 1e-9);  // log spacing: 1e2, 1e3, 1e4
}

TEST(StudySpec, ErrorsNameTheField) {
  EXPECT_NE(error_of(R"("parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.3}},
                        "design": {"type": "latin", "samples": 3}, "qoi": ["t_min"])").find("design.type"), std::string::npos);
  EXPECT_NE(error_of(R"("parameters": {"M0_11": {"distribution": "normal", "from_config": true},
                                       "s_structure.preload_mean[0]": {"distribution": "uniform", "min": 1, "max": 2}},
                        "design": {"type": "sobol", "samples": 3}, "qoi": ["t_min"])").find("same parameter"), std::string::npos);
  EXPECT_NE(error_of(R"("parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.3}},
                        "qoi": ["t_min"])").find("design"), std::string::npos);
  EXPECT_NE(error_of(R"("parameters": {"c_q": {"distribution": "uniform", "min": 0.1, "max": 0.3}},
                        "design": {"type": "sobol", "samples": 3}, "qoi": ["t_min"], "channels": ["Bl_z"])").find("B_l_z"),
            std::string::npos);
}

TEST(StudySpec, ARefusedStartingPointIsNamedByTheValueTried) {
  // The scenario sets no initial_u.z: the checks start at its median, -1000 m/s,
  // which the model refuses; values near 0 it takes.
  const std::string uniform = R"("scenario.initial_u.z": {"distribution": "uniform", "min": -2000, "max": 0})";
  for (const std::string& parameters : {uniform, R"("c_q": {"distribution": "uniform", "min": 0.1, "max": 0.3}, )" + uniform}) {
    const std::string e = error_of(R"("parameters": {)" + parameters + R"(},
                                      "design": {"type": "sobol", "samples": 4}, "qoi": ["t_min"])");
    SCOPED_TRACE(parameters);
    EXPECT_NE(e.find("'scenario.initial_u.z' at -1000, the median of its uniform"), std::string::npos) << e;
    EXPECT_NE(e.find("z = -1000 m/s is beyond +-10 m/s"), std::string::npos) << e;
    EXPECT_EQ(e.find("cannot vary alone"), std::string::npos) << e;
    EXPECT_EQ(e.find("'c_q'"), std::string::npos) << e;
  }
  EXPECT_EQ(error_of(R"("parameters": {"scenario.initial_u.z": {"distribution": "uniform", "min": -2, "max": 0}},
                        "design": {"type": "sobol", "samples": 4}, "qoi": ["t_min"])"), "");
}

TEST(StudySpec, AnInputThatCannotVaryAloneNamesTheValuesTried) {
  // An off-diagonal inertia entry whose symmetric partner stays put.
  const std::string e = error_of(R"("parameters": {"bodies.chassis.inertia[0][1]": {"distribution": "uniform", "min": -1e-4, "max": 1e-4}},
                                    "design": {"type": "sobol", "samples": 4}, "qoi": ["t_min"])");
  EXPECT_NE(e.find("cannot vary alone: the model takes it at its configured value "), std::string::npos) << e;
  EXPECT_NE(e.find(" but refuses "), std::string::npos) << e;
  EXPECT_NE(e.find("symmetric"), std::string::npos) << e;  // the model's reason
}

}  // namespace
}  // namespace rover::study
