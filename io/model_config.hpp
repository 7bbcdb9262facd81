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

// Reads an optional "params" object {"f", "c_q", "M0": [8], "w_ref": [4],
// "d_ref": [4]} over `base`; absent keys keep the base value.
ModelInputs parse_model_inputs(const JsonReader& params, ModelInputs base);

}  // namespace rover::io
