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
// The rover file's other numbers have bounds about two orders of magnitude
// beyond the paper's values (configs/rover.json), where only a unit mistake
// lands (millimetres, kg mm^2, degrees, percent, mN m, mm/s):
//   * lengths (geometry, centres of mass) within kMaxRoverLength_m: the
//     rover is 0.4 m long and its wheels 8.5 cm in radius;
//   * inertia tensor entries within kMaxBodyInertia_kgm2: the chassis's
//     largest is 0.015 kg m^2;
//   * the S-structure's stiffness k_q within kMaxSStructureStiffness_Nm_per_rad
//     (paper 9.91 N m/rad);
//   * the steering gains K_d and end-stop stiffness within
//     kMaxSteeringStiffness_Nm_per_rad (paper 20 and 200 N m/rad), the
//     steering and drive dampings D_d and K_w within kMaxDamping_Nms_per_rad
//     (paper 0.2 and 0.3 N m s/rad);
//   * the steering limit within kMaxSteeringLimit_rad, a full turn (paper
//     1.7453 rad, which is 100 degrees);
//   * the drive torque tau_max within kMaxDriveTorque_Nm (paper 4.1 N m);
//   * the ground's stiffness k_g, damping c_g and exponent sigma within
//     kMaxGroundStiffness, kMaxGroundDamping and kMaxContactExponent (paper
//     1e6, 100, 1.8; at an exponent of 10 a millimetre's penetration pushes
//     with 1e-22 N at the largest stiffness: no contact at all);
//   * the friction coefficients mu_s, mu_k within kMaxFrictionCoefficient
//     (paper 0.3, 0.2; real contacts stay below about 1.5) and the Stribeck
//     speeds v_s, v_k within kMaxStribeckSpeed_mps (paper 0.55 and 2 mm/s).
#pragma once

#include <cmath>
#include <numbers>
#include <string>

#include "core/number_text.hpp"

namespace rover {

inline constexpr double kMaxCoordinate_m = 1e6;
inline constexpr double kMinTerrainSpacing_m = 1e-6;
inline constexpr double kMaxDriveSpeed_mps = 10.0;
inline constexpr double kMaxYawRate_radps = 10.0;
// An S-structure joint deflects by degrees under the rover's weight; a
// quarter turn folds the leg into the chassis.
inline constexpr double kMaxSStructureDeflection_rad = std::numbers::pi / 2.0;
// The chassis's pitch and roll start within degrees of level; beyond a
// quarter turn the rover stands on its end or its side (and at pitch +-pi/2
// the Euler angles are singular). The bogie pivot folds into the chassis
// there too. A heading or a wheel's rolling angle beyond a full turn equals
// one within it. Beyond these bounds an angle is one in degrees.
inline constexpr double kMaxChassisTilt_rad = std::numbers::pi / 2.0;
inline constexpr double kMaxBogieAngle_rad = std::numbers::pi / 2.0;
inline constexpr double kMaxTurnAngle_rad = 2.0 * std::numbers::pi;
inline constexpr double kMaxSharpness_per_rad = 1e8;
// Below this the transition of atan(f b) is wider than any joint angle: the
// preload never acts (paper: f 1e2 .. 1e5 1/rad).
inline constexpr double kMinSharpness_per_rad = 1.0;
inline const std::string kSharpnessBelowScaleReason =
    "the transition of atan(f b) is then wider than any joint angle and the preload never acts (paper: f 1e2 .. "
    "1e5 1/rad); a unit mistake?";
inline constexpr double kMaxDamping_Nms_per_rad = 1e3;
inline constexpr double kMaxPreload_Nm = 1e3;
inline constexpr double kMaxGravity_mps2 = 1e2;
inline constexpr double kMaxBodyMass_kg = 1e2;
// A body lighter than 10 g (1e-30 kg, or 1.3e-3 kg: the chassis in tonnes)
// is a unit mistake too: the rover's lightest body, a leg module, weighs
// 0.079 kg.
inline constexpr double kMinBodyMass_kg = 1e-2;
inline constexpr double kMaxRoverLength_m = 10.0;
// A wheel smaller than a millimetre is a unit mistake (8.5e-5: the paper's
// 8.5 cm in kilometres).
inline constexpr double kMinWheelRadius_m = 1e-3;
inline constexpr double kMaxBodyInertia_kgm2 = 1.0;
inline constexpr double kMaxSStructureStiffness_Nm_per_rad = 1e3;
inline constexpr double kMaxSteeringStiffness_Nm_per_rad = 1e4;
inline constexpr double kMaxSteeringLimit_rad = 2.0 * std::numbers::pi;
inline constexpr double kMaxDriveTorque_Nm = 1e2;
inline constexpr double kMaxGroundStiffness = 1e8;  // N/m^sigma
inline constexpr double kMaxGroundDamping = 1e4;    // N s/m
inline constexpr double kMaxContactExponent = 10.0;
inline constexpr double kMaxFrictionCoefficient = 10.0;
inline constexpr double kMaxStribeckSpeed_mps = 0.1;
// Below 1 um/s (the paper's v_s is 550 um/s) a Stribeck speed is a unit
// mistake (km/s, 1e-300): the stick-slip transition sharpens as 1/v and a
// drop's cost grows as 1/v^2 (a 1-s drop at v_s 1 um/s takes minutes).
inline constexpr double kMinStribeckSpeed_mps = 1e-6;

// Empty if |value| <= bound; otherwise "1e+308 m is beyond +-1e+06 m, <why>".
inline std::string beyond_scale(double value, double bound, const std::string& unit, const std::string& why) {
  if (std::abs(value) <= bound) return "";
  const std::string u = unit.empty() ? "" : " " + unit;  // none for a coefficient
  return number_text(value) + u + " is beyond +-" + number_text(bound) + u + ", " + why;
}

// Empty if value >= bound; otherwise "1e-300 m/s is below 1e-06 m/s, <why>".
inline std::string below_scale(double value, double bound, const std::string& unit, const std::string& why) {
  if (value >= bound) return "";
  return number_text(value) + " " + unit + " is below " + number_text(bound) + " " + unit + ", " + why;
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
inline const std::string kLengthScaleReason =
    "far beyond the rover's size (0.4 m long, wheels of 8.5 cm radius); a unit mistake (millimetres)?";
inline const std::string kInertiaScaleReason =
    "far beyond the rover's bodies (at most 0.015 kg m^2); a unit mistake (kg mm^2, g cm^2)?";
inline const std::string kJointScaleReason =
    "orders of magnitude beyond the rover's joints (paper: k_q 9.91 N m/rad, K_d 20 N m/rad, end stops "
    "200 N m/rad, D_d 0.2 and K_w 0.3 N m s/rad); a unit mistake?";
inline const std::string kSteeringLimitScaleReason =
    "beyond a full turn of the steering (paper: 1.7453 rad); a unit mistake (degrees)?";
inline const std::string kDriveTorqueScaleReason =
    "far beyond the rover's wheel motors (paper: 4.1 N m); a unit mistake (mN m)?";
inline const std::string kContactScaleReason =
    "orders of magnitude beyond the paper's ground (k_g 1e6 N/m^sigma, c_g 100, sigma 1.8); a unit mistake?";
inline const std::string kFrictionScaleReason =
    "far beyond any contact's friction (paper: mu_s 0.3, mu_k 0.2); a unit mistake (percent)?";
inline const std::string kStribeckScaleReason =
    "far beyond the paper's stick-slip speeds (v_s 0.55 mm/s, v_k 2 mm/s); a unit mistake (mm/s)?";
inline const std::string kStribeckBelowScaleReason =
    "far below the paper's stick-slip speeds (v_s 0.55 mm/s, v_k 2 mm/s), where a drop's cost grows as 1/v^2; "
    "a unit mistake (km/s)?";
inline const std::string kWheelRadiusBelowScaleReason =
    "far below the rover's wheels (8.5 cm radius); a unit mistake (kilometres)?";
inline const std::string kDeflectionScaleReason =
    "a quarter turn, where the leg folds into the chassis (an S-structure deflects by degrees); an angle in "
    "degrees?";
inline const std::string kChassisTiltScaleReason =
    "a quarter turn, where the rover stands on its end or its side (a drop starts within degrees of level); an "
    "angle in degrees?";
inline const std::string kBogieAngleScaleReason =
    "a quarter turn, where the bogie folds into the chassis; an angle in degrees?";
inline const std::string kHeadingScaleReason =
    "a full turn (a heading beyond it equals one within); an angle in degrees?";
inline const std::string kWheelAngleScaleReason =
    "a full turn (a wheel's rolling angle beyond it equals one within); an angle in degrees?";
inline const std::string kDriveScaleReason =
    "far beyond what the rover drives (decimetres per second); a unit mistake?";

}  // namespace rover
