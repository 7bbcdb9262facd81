// See scenario_config.hpp.
#include "io/scenario_config.hpp"

#include <filesystem>

#include "core/kinematic_tree.hpp"
#include "io/model_config.hpp"

namespace rover::io {
namespace {

int coordinate_index(const JsonReader& r, const std::string& name) {
  for (int i = 0; i < kNumCoordinates; ++i)
    if (name == kCoordinateNames[i]) return i;
  r.fail(name, "unknown coordinate name (use x y z theta chi psi phi b11 b12 b21 b22 b31 b32 b41 "
               "b42 d1 d2 d3 d4 z1 z2 z3 z4)");
}

Coordinates parse_named_coordinates(const JsonReader& parent, const std::string& key) {
  Coordinates c = Coordinates::Zero();
  if (!parent.has(key)) return c;
  const JsonReader r = parent.child(key);
  for (const auto& [name, value] : r.raw_object().items()) c[coordinate_index(r, name)] = r.number(name);
  r.finish();
  return c;
}

// Lowest wheel-bottom height below the chassis origin at the given pose.
double lowest_wheel_bottom(const RoverModel& model, const Coordinates& q) {
  Coordinates level = q;
  level[coord::z] = 0.0;
  const TreeKinematics kin = forward_kinematics(model.tree, level, Coordinates::Zero());
  double lowest = std::numeric_limits<double>::infinity();
  const double R = model.parameters.geometry.wheel_radius_m;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const NodeKinematics& w = kin.nodes[node::wheel(leg)];
    const Vec3 s = w.rotation.col(1);
    lowest = std::min(lowest, w.origin.z() - R * std::sqrt(std::max(0.0, 1.0 - s.z() * s.z())));
  }
  return lowest;
}

}  // namespace

std::string resolve_relative(const std::string& config_path, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return path;
  return (std::filesystem::path(config_path).parent_path() / p).lexically_normal().string();
}

IntegratorSettings parse_integrator_settings(const JsonReader& r, IntegratorSettings s) {
  if (r.has("method")) {
    try {
      s.method = integrator_from_name(r.string("method"));
    } catch (const std::invalid_argument& e) {
      r.fail("method", e.what());
    }
  }
  if (r.has("rtol")) s.relative_tolerance = r.positive("rtol");
  if (r.has("atol")) s.absolute_tolerance = r.positive("atol");
  if (r.has("initial_step")) s.initial_step_s = r.positive("initial_step");
  if (r.has("min_step")) s.min_step_s = r.positive("min_step");
  if (r.has("max_step")) s.max_step_s = r.positive("max_step");
  if (r.has("fixed_step")) s.fixed_step_s = r.positive("fixed_step");
  r.finish();
  return s;
}

SimulationInputs parse_simulation_inputs(const JsonReader& r, SimulationInputs in) {
  if (r.has("f")) in.sharpness_f = r.positive("f");
  if (r.has("c_q")) in.damping_c_q = r.non_negative("c_q");
  if (r.has("M0")) in.preload_Nm = r.fixed_numbers<kNumSJoints>("M0");
  r.finish();
  return in;
}

ScenarioSetup load_scenario(const std::string& path) {
  const Json json = read_json_file(path);
  const JsonReader r(json, path);
  ScenarioSetup setup;
  setup.scenario_path = path;
  Scenario& s = setup.scenario;
  s.name = r.string_or("name", std::filesystem::path(path).stem().string());
  r.string_or("description", "");
  setup.rover_path = resolve_relative(path, r.string("rover"));
  if (r.has("terrain")) setup.terrain_path = resolve_relative(path, r.string("terrain"));
  if (!std::filesystem::exists(setup.rover_path))
    r.fail("rover", "file not found: " + setup.rover_path);
  if (!setup.terrain_path.empty() && !std::filesystem::exists(setup.terrain_path))
    r.fail("terrain", "file not found: " + setup.terrain_path);
  setup.model = load_rover_model(setup.rover_path, setup.terrain_path);
  const double R = setup.model.parameters.geometry.wheel_radius_m;

  s.initial_q = parse_named_coordinates(r, "initial_q");
  s.initial_u = parse_named_coordinates(r, "initial_u");
  if (r.has("forward_speed")) {
    const double v = r.number("forward_speed");
    s.initial_u[coord::x] = v;
    for (int leg = 0; leg < kNumLegs; ++leg) {
      s.initial_u[coord::spin(leg)] = v / R;
      s.wheel_speed_ref_radps[leg] = v / R;
    }
  }
  if (r.has("initial_ground_clearance"))
    s.initial_q[coord::z] = r.number("initial_ground_clearance") - lowest_wheel_bottom(setup.model, s.initial_q);
  if (r.has("wheel_speed_ref")) s.wheel_speed_ref_radps = r.fixed_numbers<kNumLegs>("wheel_speed_ref");
  if (r.has("steer_ref")) s.steer_ref_rad = r.fixed_numbers<kNumLegs>("steer_ref");

  if (r.has("duration") == r.has("travel_distance"))
    r.fail("duration", "give exactly one of 'duration' [s] and 'travel_distance' [m]");
  if (r.has("duration")) {
    s.duration_s = r.positive("duration");
  } else {
    const double distance = r.positive("travel_distance");
    if (!r.has("forward_speed") || !(r.number("forward_speed") > 0.0))
      r.fail("travel_distance", "needs a positive 'forward_speed'");
    s.duration_s = distance / r.number("forward_speed");
  }
  s.output_rate_hz = r.has("output_rate") ? r.positive("output_rate") : 1000.0;
  if (r.has("integrator")) s.integrator = parse_integrator_settings(r.child("integrator"), s.integrator);
  if (r.has("wall_time_budget")) s.wall_time_budget_s = r.positive("wall_time_budget");

  setup.inputs = nominal_simulation_inputs(setup.model.parameters);
  if (r.has("inputs")) setup.inputs = parse_simulation_inputs(r.child("inputs"), setup.inputs);
  r.finish();
  return setup;
}

}  // namespace rover::io
