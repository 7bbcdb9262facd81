// Numbers in error messages: the shortest readable form, "%.10g"
// (std::to_string prints 1e-12 as 0.000000, which hides the bad value).
#pragma once

#include <cstdio>
#include <string>

namespace rover {

inline std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

}  // namespace rover
