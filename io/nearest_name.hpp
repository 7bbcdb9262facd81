// The known name nearest to a mistyped one, by the optimal string alignment
// distance (Levenshtein distance with adjacent transpositions, Damerau 1964):
// "simulat" -> "simulate", "--scenaro" -> "--scenario", "distribuion" ->
// "distribution".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace rover::io {

// Insertions, deletions, substitutions and transpositions of adjacent
// characters, each costing 1.
std::size_t edit_distance(std::string_view a, std::string_view b);

// The name of `known` nearest to `typed` when near enough (at most 2 edits, or a
// third of the name for long names); otherwise the only known name that begins
// with the same word as a multi-word `typed` ("--crab-angle" -> "--crab-deg");
// empty when neither exists.
std::string nearest_name(std::string_view typed, const std::vector<std::string>& known);

}  // namespace rover::io
