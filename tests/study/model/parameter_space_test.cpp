// Parameter names mirror the configs; aliases; values applied are the values
// the loaders see (also through a scenario's "inputs" override).
#include "study/model/parameter_space.hpp"

#include <gtest/gtest.h>

#include "io/scenario_config.hpp"

namespace rover::study {
namespace {

io::ScenarioSources drop() { return io::read_scenario_sources(ROVER_SOURCE_DIR "/configs/scenarios/drop_horizontal.json"); }

TEST(ParameterSpace, NamesMirrorTheConfigsAndAliasesResolve) {
  const io::ScenarioSources s = drop();
  const ParameterSpace space(s.rover, s.scenario);
  for (const char* name : {"s_structure.f", "s_structure.c_q", "s_structure.k_q", "contact.k_g", "contact.c_g",
                           "friction.mu_s", "friction.v_s", "bodies.chassis.mass", "bodies.wheel.mass",
                           "geometry.wheel_radius", "steering.K_d", "drive.K_w", "scenario.initial_q.z",
                           "scenario.forward_speed", "bodies.chassis.inertia[0][0]"})
    EXPECT_EQ(space.canonical(name), name);
  EXPECT_EQ(space.canonical("f"), "s_structure.f");
  EXPECT_EQ(space.canonical("c_q"), "s_structure.c_q");
  EXPECT_EQ(space.canonical("M0_11"), "s_structure.preload_mean[0]");
  EXPECT_EQ(space.canonical("s_structure.M0_42"), "s_structure.preload_mean[7]");
  EXPECT_DOUBLE_EQ(space.nominal("s_structure.preload_mean[7]"), 1.117);
  EXPECT_DOUBLE_EQ(space.nominal("scenario.initial_q.z"), 0.281);
  EXPECT_TRUE(std::isnan(space.nominal("scenario.forward_speed")));
  for (const char* excluded : {"friction.gammas[0]", "scenario.duration", "scenario.output_rate"})
    EXPECT_FALSE(space.contains(excluded)) << excluded;
}

TEST(ParameterSpace, UnknownNamesSuggestTheClosest) {
  const io::ScenarioSources s = drop();
  const ParameterSpace space(s.rover, s.scenario);
  try {
    space.canonical("contact.kg");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'contact.k_g'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bodies.wheel.mass"), std::string::npos);
  }
}

TEST(ParameterSpace, AppliedValuesReachTheBuiltModel) {
  io::ScenarioSources s = drop();
  s.scenario["inputs"] = {{"c_q", 0.5}};  // the scenario overrides the rover file's c_q
  const ParameterSpace space(s.rover, s.scenario);
  EXPECT_DOUBLE_EQ(space.nominal("s_structure.c_q"), 0.5);
  space.apply("s_structure.c_q", 0.33, s.rover, s.scenario);
  space.apply("s_structure.preload_mean[3]", 1.5, s.rover, s.scenario);
  space.apply("bodies.chassis.mass", 2.0, s.rover, s.scenario);
  space.apply("scenario.initial_q.z", 0.3, s.rover, s.scenario);
  space.apply("scenario.forward_speed", 0.5, s.rover, s.scenario);
  const io::ScenarioSetup setup = io::build_scenario(s);
  EXPECT_EQ(setup.inputs.damping_c_q, 0.33);
  EXPECT_EQ(setup.inputs.preload_Nm[3], 1.5);
  EXPECT_EQ(setup.model.parameters.chassis.mass_kg, 2.0);
  EXPECT_EQ(setup.scenario.initial_q[coord::z], 0.3);
  EXPECT_EQ(setup.scenario.initial_u[coord::x], 0.5);
  EXPECT_DOUBLE_EQ(setup.scenario.wheel_speed_ref_radps[0], 0.5 / 0.085);
}

TEST(ParameterSpace, AnInvalidValueIsRejectedByTheLoaderWithTheField) {
  io::ScenarioSources s = drop();
  const ParameterSpace space(s.rover, s.scenario);
  space.apply("bodies.wheel.mass", -0.1, s.rover, s.scenario);
  try {
    io::build_scenario(s);
    FAIL();
  } catch (const io::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies.wheel.mass"), std::string::npos) << e.what();
  }
}


// M0_scale multiplies every preload: beside a single preload the run would
// depend on the order the two are applied in, so they overlap, as a name does
// with itself; other pairs do not.
TEST(ParameterSpace, TheFactorOfThePreloadsOverlapsEachPreload) {
  const io::ScenarioSources s = drop();
  const ParameterSpace space(s.rover, s.scenario);
  const std::string scale = space.canonical("M0_scale");
  for (int i = 0; i < 8; ++i) {
    const std::string preload = space.canonical(preload_alias(i));
    EXPECT_TRUE(parameters_overlap(scale, preload)) << preload;
    EXPECT_TRUE(parameters_overlap(preload, scale)) << preload;
    const std::string why = overlap_reason(preload, scale);
    EXPECT_NE(why.find("M0_scale"), std::string::npos) << why;
    EXPECT_NE(why.find(preload_alias(i) + " (" + preload + ")"), std::string::npos) << why;
  }
  EXPECT_TRUE(parameters_overlap(space.canonical("c_q"), space.canonical("s_structure.c_q")));
  EXPECT_FALSE(parameters_overlap(space.canonical("M0_11"), space.canonical("M0_12")));
  EXPECT_FALSE(parameters_overlap(scale, space.canonical("c_q")));
  EXPECT_EQ(overlap_reason(scale, space.canonical("c_q")), "");
  // Applied in either order, the two give different preloads: the reason for the rule.
  io::ScenarioSources first = drop(), second = drop();
  space.apply(scale, 1.2, first.rover, first.scenario);
  space.apply(space.canonical("M0_11"), 2.0, first.rover, first.scenario);
  space.apply(space.canonical("M0_11"), 2.0, second.rover, second.scenario);
  space.apply(scale, 1.2, second.rover, second.scenario);
  EXPECT_NE(io::build_scenario(first).inputs.preload_Nm[0], io::build_scenario(second).inputs.preload_Nm[0]);
}

}  // namespace
}  // namespace rover::study
