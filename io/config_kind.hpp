// The kinds of rover's JSON input files (rover, scenario, study, terrain,
// next-experiment candidates), told apart by their top-level keys, so that a
// file given where another kind belongs is named for what it is.
#pragma once

#include <string>

#include "io/json_reader.hpp"

namespace rover::io {

enum class ConfigKind { kRover, kScenario, kStudy, kTerrain, kCandidates, kUnknown };

// What a parsed config is: a rover (its "bodies"), a scenario (it names its
// "rover"), a study (a "type" with a "scenario", "model" or "design"), a
// terrain (a terrain's "type": flat, grid, control_points, without them), a
// candidates file ("candidates").
ConfigKind config_kind(const Json& config);

// "study file", "rover file", ...
std::string config_kind_name(ConfigKind kind);

// Throws ConfigError when `config` (read from `file`) is a config of another
// kind than `wanted`: "file: field 'type' (value "montecarlo"): this is a
// study file (its "type" and "scenario"), not a scenario file: give ...".
void refuse_other_config_kind(const Json& config, const std::string& file, ConfigKind wanted);

// read_json_file() for a config of kind `wanted`, refusing first a CSV or
// other text data file (a name ending in .csv that holds no JSON object, or
// a first line that is a '#' comment), then a config of another kind.
Json read_config_file(const std::string& path, ConfigKind wanted);

}  // namespace rover::io
