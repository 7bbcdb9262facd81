// A refused command line in rover's words: what was typed, at which flag,
// and what the flag accepts; never CLI11's own text ("The following argument
// was not expected", "Could not convert", "Value 0 not in range ...").
//
// A mistyped name gets the nearest known one (io/nearest_name.hpp):
// "rover simulat" -> did you mean 'simulate'? "--scenaro" -> did you mean
// '--scenario'? A flag given twice, a known option after '--', an empty
// "--seed=" and an em dash for "--" are named as typed.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

#include "io/nearest_name.hpp"

namespace rover::cli {

// The nearest known name to a mistyped one (io/nearest_name.hpp).
using io::nearest_name;

// How an option whose value is missing is reported ("--out was given no
// value: the word after it, '--no-plot', is an option of its own"), whether
// CLI11 took the next option as its value or a validator refused it.
inline constexpr std::string_view kGivenNoValue = "was given no value";

// The lines to print for `error`, raised while parsing the command line of
// `command` (the subcommands typed, "terrain obstacle"; empty when none was
// recognised): "rover <command>: error: ...", then a pointer to --help.
// `args` are the words after `rover`, as typed.
std::vector<std::string> command_line_error_lines(const CLI::ParseError& error, const CLI::App& app,
                                                  const std::string& command, const std::vector<std::string>& args);

// The lines to print for words of `args` that CLI11 would misread, checked
// before parsing (empty if none): "--seed=" with nothing after the '=' (CLI11
// would take the next word as its value), a word starting with a dash that is
// not '-' (an em dash before "scenario", pasted from a document).
std::vector<std::string> typed_word_error_lines(const std::vector<std::string>& args, const CLI::App& app,
                                                const std::string& command);

}  // namespace rover::cli
