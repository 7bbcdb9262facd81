// Loads RoverParameters (docs/model.md §3–6) from a JSON config such as
// configs/rover.json. Every field is required (no silent defaults for the
// physics), unknown keys are rejected, and each error names the file, the
// field and the value.
#pragma once

#include <array>
#include <string>

#include "core/rover_parameters.hpp"
#include "io/json_reader.hpp"

namespace rover::io {

RoverParameters load_rover_parameters(const std::string& path);

// The S-structure quantities wherever a config gives them (rover.json's
// s_structure, a scenario's or a study's "inputs"): f in (0, 1e8] 1/rad,
// c_q in [0, 1e3] N m s/rad, each preload in [0, 1e3] N m
// (core/model_scale.hpp). A ConfigError names the field and the value.
double read_sharpness_f(const JsonReader& r, const std::string& key);
double read_damping_c_q(const JsonReader& r, const std::string& key);
std::array<double, kNumSJoints> read_preloads(const JsonReader& r, const std::string& key);
RoverParameters parse_rover_parameters(const Json& config, const std::string& file_name);

}  // namespace rover::io
