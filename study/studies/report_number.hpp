// Numbers in study reports and result attributes: a given number of
// significant digits ("%.4g" by default).
#pragma once

#include <cstdio>
#include <string>

namespace rover::study {

inline std::string format_number(double v, int significant_digits = 4) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", significant_digits, v);
  return buffer;
}

}  // namespace rover::study
