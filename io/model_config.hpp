// Builds a RoverModel from files: the rover config (configs/rover.json) and,
// optionally, a terrain file (configs/terrains/*.json; flat z = 0 if empty).
#pragma once

#include <string>

#include "core/model_inputs.hpp"
#include "core/rover_model.hpp"
#include "io/json_reader.hpp"

namespace rover::io {

RoverModel load_rover_model(const std::string& rover_config_path,
                            const std::string& terrain_path = "");

// make_rover_model(), with a failure to synthesise the friction gammas for
// the file's (mu_s, v_s, mu_k, v_k) turned into a ConfigError naming the
// file, the field 'friction' and the four values.
RoverModel make_checked_rover_model(RoverParameters parameters, Terrain terrain,
                                    const std::string& rover_config_path);

// Reads an optional "params" object {"f", "c_q", "M0": [8], "w_ref": [4],
// "d_ref": [4]} over `base`; absent keys keep the base value.
ModelInputs parse_model_inputs(const JsonReader& params, ModelInputs base);

}  // namespace rover::io
