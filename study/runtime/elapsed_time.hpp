// Wall time since a moment on the steady clock, in seconds: progress lines,
// run records and the analysis times a study reports.
#pragma once

#include <chrono>

namespace rover::study {

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace rover::study
