// Numbers in study reports and result attributes: a given number of
// significant digits ("%.4g" by default); a missing one named in words.
#pragma once

#include <cstdio>
#include <string>

namespace rover::study {

inline std::string format_number(double v, int significant_digits = 4) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", significant_digits, v);
  return buffer;
}

// A residual statistic that may be missing (NaN: the run failed, so there
// are no residuals): its number and unit, or "none (no residuals)".
inline std::string format_residual_statistic(double v, int significant_digits, const std::string& unit = "") {
  if (v != v) return "none (no residuals)";
  return format_number(v, significant_digits) + (unit.empty() ? "" : " " + unit);
}

}  // namespace rover::study
