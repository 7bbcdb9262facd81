// See model_config.hpp.
#include "io/model_config.hpp"

#include "core/number_text.hpp"
#include "io/rover_config.hpp"
#include "io/terrain_json.hpp"

namespace rover::io {

RoverModel make_checked_rover_model(RoverParameters parameters, Terrain terrain,
                                    const std::string& rover_config_path) {
  const FrictionParameters friction = parameters.friction;
  try {
    return make_rover_model(std::move(parameters), std::move(terrain));
  } catch (const std::exception& e) {
    throw ConfigError(rover_config_path + ": field 'friction' (mu_s " + number_text(friction.mu_static) +
                      ", v_s " + number_text(friction.v_static_mps) + ", mu_k " +
                      number_text(friction.mu_kinetic) + ", v_k " + number_text(friction.v_kinetic_mps) +
                      "): no Makkar gammas can be synthesised for this law (" + e.what() + ")");
  }
}

RoverModel load_rover_model(const std::string& rover_config_path, const std::string& terrain_path) {
  RoverParameters parameters = load_rover_parameters(rover_config_path);
  Terrain terrain = terrain_path.empty() ? Terrain::flat() : load_terrain(terrain_path);
  return make_checked_rover_model(std::move(parameters), std::move(terrain), rover_config_path);
}

ModelInputs parse_model_inputs(const JsonReader& r, ModelInputs in) {
  if (r.has("f")) in.sharpness_f = read_sharpness_f(r, "f");
  if (r.has("c_q")) in.damping_c_q = read_damping_c_q(r, "c_q");
  if (r.has("M0")) in.preload_Nm = read_preloads(r, "M0");
  if (r.has("w_ref")) in.wheel_speed_ref_radps = r.fixed_numbers<kNumLegs>("w_ref");
  if (r.has("d_ref")) in.steer_ref_rad = r.fixed_numbers<kNumLegs>("d_ref");
  r.finish();
  return in;
}

}  // namespace rover::io
