// Loads RoverParameters (docs/model.md §3–6) from a JSON config such as
// configs/rover.json. Every field is required (no silent defaults for the
// physics), unknown keys are rejected, and each error names the file, the
// field and the value.
#pragma once

#include <string>

#include "core/rover_parameters.hpp"
#include "io/json_reader.hpp"

namespace rover::io {

RoverParameters load_rover_parameters(const std::string& path);
RoverParameters parse_rover_parameters(const Json& config, const std::string& file_name);

}  // namespace rover::io
