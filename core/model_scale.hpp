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
// are unit mistakes too. The S-structure's sharpness f, damping c_q and
// preloads M0 have bounds of the same kind: the paper's values are f 1e2 ..
// 1e5 1/rad, c_q about 0.1 N m s/rad, M0 about 2 N m (the rover's weight
// loads a joint with about 1e2 N m); beyond kMaxSharpness_per_rad the
// transition of atan(f b) is narrower than the integrators resolve an angle,
// and a damping or preload four orders of magnitude beyond the paper's makes
// the drop a stiff problem no integrator finishes in its wall-time budget.
// A gravity beyond kMaxGravity_mps2 (ten Earths) or a body heavier than
// kMaxBodyMass_kg (the rover's bodies weigh 0.08 .. 1.3 kg) is a unit
// mistake: 981 cm/s^2, a mass in grams.
#pragma once

#include <cmath>
#include <string>

#include "core/number_text.hpp"

namespace rover {

inline constexpr double kMaxCoordinate_m = 1e6;
inline constexpr double kMinTerrainSpacing_m = 1e-6;
inline constexpr double kMaxDriveSpeed_mps = 10.0;
inline constexpr double kMaxYawRate_radps = 10.0;
inline constexpr double kMaxSharpness_per_rad = 1e8;
inline constexpr double kMaxDamping_Nms_per_rad = 1e3;
inline constexpr double kMaxPreload_Nm = 1e3;
inline constexpr double kMaxGravity_mps2 = 1e2;
inline constexpr double kMaxBodyMass_kg = 1e2;

// Empty if |value| <= bound; otherwise "1e+308 m is beyond +-1e+06 m, <why>".
inline std::string beyond_scale(double value, double bound, const std::string& unit, const std::string& why) {
  if (std::abs(value) <= bound) return "";
  return number_text(value) + " " + unit + " is beyond +-" + number_text(bound) + " " + unit + ", " + why;
}

inline const std::string kPositionScaleReason =
    "where a double no longer resolves the rover's motion (docs/reliability.md)";
inline const std::string kSStructureScaleReason =
    "orders of magnitude beyond the rover's S-structure (paper: f 1e2 .. 1e5 1/rad, c_q ~0.1 N m s/rad, "
    "M0 ~2 N m); a unit mistake?";
inline const std::string kGravityScaleReason =
    "far beyond any planet's surface gravity (Earth 9.81 m/s^2, Mars 3.71 m/s^2); a unit mistake?";
inline const std::string kBodyMassScaleReason =
    "far beyond the rover's bodies (0.08 .. 1.3 kg); a unit mistake?";
inline const std::string kDriveScaleReason =
    "far beyond what the rover drives (decimetres per second); a unit mistake?";

}  // namespace rover
