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

}  // namespace
}  // namespace rover::study
