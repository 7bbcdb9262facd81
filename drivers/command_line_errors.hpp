// A refused command line in rover's words: what was typed, at which flag,
// and what the flag accepts; never CLI11's own text ("The following argument
// was not expected", "Could not convert", "Value 0 not in range ...").
//
// A mistyped name gets the nearest known one by the optimal string alignment
// distance (Levenshtein distance with adjacent transpositions, Damerau 1964):
// "rover simulat" -> did you mean 'simulate'? "--scenaro" -> did you mean
// '--scenario'?
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

namespace rover::cli {

// The name of `known` nearest to `typed` when near enough (at most 2 edits, or a
// third of the name for long names); empty otherwise.
std::string nearest_name(std::string_view typed, const std::vector<std::string>& known);

// The lines to print for `error`, raised while parsing the command line of
// `command` (the subcommands typed, "terrain obstacle"; empty when none was
// recognised): "rover <command>: error: ...", then a pointer to --help.
std::vector<std::string> command_line_error_lines(const CLI::ParseError& error, const CLI::App& app,
                                                  const std::string& command);

}  // namespace rover::cli
