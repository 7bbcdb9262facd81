// The scales beyond which a finite number no longer describes the rover.
//
// The model resolves millimetre contact penetrations with integrators whose
// absolute tolerance is 1e-9; a double's spacing at |x| is about
// 2.2e-16 |x|. At kMaxCoordinate_m = 1e6 m that spacing is 1.2e-10 m, below
// the tolerance: positions (an initial pose, a terrain's origin and extent,
// an instantaneous centre of rotation, a turn radius) up to there keep
// every step's sums exact to the tolerance; at 1e308 m a drop "runs" with
// the rover frozen by rounding. A terrain spacing below kMinTerrainSpacing_m
// is a unit mistake: the wheel radius is 8.5 cm. Commanded speeds and yaw
// rates beyond kMaxDriveSpeed_mps and kMaxYawRate_radps are two orders of
// magnitude beyond what the rover's motors drive (decimetres per second) and
// are unit mistakes too.
#pragma once

#include <cmath>
#include <string>

#include "core/number_text.hpp"

namespace rover {

inline constexpr double kMaxCoordinate_m = 1e6;
inline constexpr double kMinTerrainSpacing_m = 1e-6;
inline constexpr double kMaxDriveSpeed_mps = 10.0;
inline constexpr double kMaxYawRate_radps = 10.0;

// Empty if |value| <= bound; otherwise "1e+308 m is beyond +-1e+06 m, <why>".
inline std::string beyond_scale(double value, double bound, const std::string& unit, const std::string& why) {
  if (std::abs(value) <= bound) return "";
  return number_text(value) + " " + unit + " is beyond +-" + number_text(bound) + " " + unit + ", " + why;
}

inline const std::string kPositionScaleReason =
    "where a double no longer resolves the rover's motion (docs/reliability.md)";
inline const std::string kDriveScaleReason =
    "far beyond what the rover drives (decimetres per second); a unit mistake?";

}  // namespace rover
