// Numbers in error messages: the shortest readable form, "%.10g"
// (std::to_string prints 1e-12 as 0.000000, which hides the bad value), or
// every digit a double needs, where two values must read apart.
#pragma once

#include <charconv>
#include <cstdio>
#include <string>

namespace rover {

inline std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

// The shortest text that reads back to exactly v ("0.1000000000001").
inline std::string exact_number_text(double v) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::string(text, end);
}

}  // namespace rover
