// Driving modes: decomposition of a high-level motion command into the four
// steering angles d_j and wheel rolling speeds dz_j/dt (the paper's section
// 2.1, "Software and control"), on the geometry and sign conventions of
// docs/model.md §1–3 and the steering end-stops of section 5.
//
// The chassis moves in its own plane (x forward, y left, origin G) with a
// rigid planar motion; wheel j has its steering axis at the wheel centre r_j,
// so its centre moves with v_j = v_G + omega z x r_j. A wheel rolls without
// scrub when its heading (cos d_j, sin d_j) is parallel to v_j and its rolling
// speed is dz_j/dt = (signed ground speed) / R_w. Every command below is first
// turned into a PlanarMotion (a translation, or a rotation about an
// instantaneous centre of rotation, ICR), which fixes each wheel's line of
// rolling, then into wheel states.
//
// Which heading serves a line of rolling: every motion has a positive sense,
// the sense in which its speed parameter is positive (the forward/left
// conventions are documented per constructor). The *nominal* heading of a
// wheel is the direction its centre moves in that sense, so the wheel rolls
// forward when the speed is positive and backward when it is negative, and
// the steering does not move when the speed passes through zero. A nominal
// heading beyond the end-stop |d| <= limit is either
//   * served by flipping the wheel: heading d -+ pi with the rolling speed
//     reversed (the same wheel-centre velocity, so still no scrub), when
//     WheelCommandOptions::allow_flip is set (the default; the hub motors have
//     no preferred rolling direction), or
//   * rejected with std::invalid_argument naming the mode, the wheel, the
//     needed angle and the limit.
// A heading is never clamped to the limit (a clamped wheel would fight the
// others). With the default limit (100 deg > 90 deg) every line of rolling can
// be served with the flip; with a limit below 90 deg some cannot, and those
// commands are rejected whatever the flip setting.
//
// Modes and the body velocities (v_x, v_y, omega at G) each can represent:
//   car-like            front wheels steer, rear wheels fixed straight (d = 0):
//                       the ICR lies on the rear-axle line, i.e. the rear-axle
//                       centre moves straight ahead: v_y + omega x_rear = 0.
//   symmetric Ackermann front and rear wheels steer opposite: the ICR lies on
//                       the lateral line through the midpoint of the front and
//                       rear axles: v_y + omega x_mid = 0 (x_mid = 0 for the
//                       default, fore-aft symmetric rover).
//   general Ackermann   any ICR, i.e. any (v_x, v_y, omega).
//   parallel (crab)     all wheels parallel: omega = 0.
//   lateral             all wheels at +90 deg: omega = 0 and v_x = 0.
//   in-place rotation   about G: v_x = v_y = 0.
// A body command a mode cannot represent is rejected with a message that says
// why and which mode can serve it.
//
// Wheels with a free heading (zero body command in a mode whose geometry
// depends on the speeds, or a wheel exactly at the ICR) get zero speed and
// hold WheelCommandOptions::hold_steer_rad. Natural-parameter commands keep
// their geometry at zero speed (Ackermann at speed 0 pre-steers the wheels).
//
// Time-varying commands (wheel_commands_at) are piecewise constant, optionally
// blended over a ramp time at each segment start (see DriveScheduleOptions).
#pragma once

#include <array>
#include <optional>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "core/rover_parameters.hpp"

namespace rover {

using Vec2 = Eigen::Vector2d;

enum class DriveMode {
  kCarLike,
  kSymmetricAckermann,
  kGeneralAckermann,
  kParallel,
  kLateral,
  kInPlaceRotation
};

inline constexpr std::array<DriveMode, 6> kAllDriveModes{
    DriveMode::kCarLike,  DriveMode::kSymmetricAckermann, DriveMode::kGeneralAckermann,
    DriveMode::kParallel, DriveMode::kLateral,            DriveMode::kInPlaceRotation};

// Human-readable name for messages ("symmetric Ackermann").
std::string_view drive_mode_name(DriveMode mode);
// Short keyword for command lines and config files: car, ackermann,
// general-ackermann, parallel, lateral, rotation.
std::string_view drive_mode_keyword(DriveMode mode);
std::optional<DriveMode> drive_mode_from_keyword(std::string_view keyword);

// Wheel names in leg order (docs/model.md §1): FL, FR, RL, RR.
inline constexpr std::array<const char*, kNumLegs> kWheelNames{"FL", "FR", "RL", "RR"};

// What the driving modes need of the rover: the steering axes (through the
// wheel centres) in the chassis xy-plane, the wheel radius and the end-stop.
struct DriveKinematics {
  std::array<Vec2, kNumLegs> wheel_centre_m{};  // r_j at q = 0, chassis frame
  double wheel_radius_m = 0.0;                  // R_w
  double steering_limit_rad = 0.0;              // |d_j| <= limit
};

// From the template geometry of docs/model.md §3 at q = 0 (mirrored as in
// the kinematic tree: the bogie pivot per side, the leg offsets per leg).
// Throws std::invalid_argument for a non-positive wheel radius or limit.
DriveKinematics make_drive_kinematics(const RoverParameters& parameters);

// Reference points of the Ackermann modes (their turning radii and speeds are
// measured there): the rear-axle centre (car-like) and the centre between the
// front and rear axle centres (symmetric Ackermann; G for the default rover).
Vec2 rear_axle_centre_m(const DriveKinematics& kinematics);
Vec2 axle_midpoint_centre_m(const DriveKinematics& kinematics);

// Body velocity of the chassis at G, chassis axes.
struct BodyVelocityCommand {
  double forward_mps = 0.0;     // v_x
  double lateral_mps = 0.0;     // v_y (+ left)
  double yaw_rate_radps = 0.0;  // omega (+ turning left)
};

// The chassis's instantaneous planar motion, in a form that fixes each wheel's
// line of rolling even at zero speed.
struct PlanarMotion {
  enum class Kind {
    kRest,         // no motion and no geometry: wheels hold
    kTranslation,  // every point moves with speed_mps along heading_rad
    kRotation      // rotation about icr_m with yaw_rate_radps
  };
  Kind kind = Kind::kRest;
  double heading_rad = 0.0;       // translation: direction of the positive sense
  double speed_mps = 0.0;         // translation: signed speed along heading_rad
  Vec2 icr_m = Vec2::Zero();      // rotation: ICR in the chassis frame
  double positive_sense = 1.0;    // rotation: +1 or -1, the yaw-rate sign of the positive sense
  double yaw_rate_radps = 0.0;    // rotation: signed yaw rate
};

// The chassis velocity at G of a motion.
BodyVelocityCommand body_velocity(const PlanarMotion& motion);

// A mode with the motion it drives.
struct DriveCommand {
  DriveMode mode = DriveMode::kGeneralAckermann;
  PlanarMotion motion;
};

// Natural parameters of each mode. Speeds are signed (negative = reversing).
// Turning radii are signed (+ = ICR on the left), +-infinity = straight ahead;
// a zero radius is only accepted at zero speed (otherwise it is a rotation
// about the reference point: use in_place_rotation_command or a body command).
//
// car-like: speed and radius of the rear-axle centre; positive = forward.
DriveCommand car_like_command(const DriveKinematics& kinematics, double speed_mps,
                              double turn_radius_m);
// symmetric Ackermann: speed and radius of axle_midpoint_centre_m; positive = forward.
DriveCommand symmetric_ackermann_command(const DriveKinematics& kinematics, double speed_mps,
                                         double turn_radius_m);
// general Ackermann: speed of G about the ICR (chassis frame). Positive = G
// moves forward (or left, if the ICR is on the x axis). The ICR must not be G.
DriveCommand general_ackermann_command(double speed_mps, const Vec2& icr_m);
// parallel: every wheel at crab_angle_rad (+ = left of forward), speed along it.
DriveCommand parallel_command(double speed_mps, double crab_angle_rad);
// lateral: every wheel at +90 deg; positive = left.
DriveCommand lateral_command(double speed_mps);
// in-place rotation about G; the positive sense is a positive yaw rate.
DriveCommand in_place_rotation_command(double yaw_rate_radps);

// A body velocity command in a mode. Throws std::invalid_argument when the
// mode cannot represent it: the velocity it would have to drop (v_y + omega x
// at the relevant point, omega, v_x) exceeds tolerance_mps (omega is compared
// as omega * 1 m). The positive sense is: G (the reference point for the
// Ackermann modes) moves forward; if it moves purely sideways, left; if it is
// at rest, a positive yaw rate. A zero command is PlanarMotion::kRest, except
// in the lateral and in-place rotation modes, whose geometry is fixed.
DriveCommand drive_command(const DriveKinematics& kinematics, DriveMode mode,
                           const BodyVelocityCommand& command, double tolerance_mps = 1e-9);

struct WheelCommandOptions {
  bool allow_flip = true;                         // see the file comment
  std::array<double, kNumLegs> hold_steer_rad{};  // steering of wheels with a free heading
  double velocity_tolerance_mps = 1e-9;           // body-command representability
  double position_tolerance_m = 1e-12;            // a wheel this close to the ICR is at it
  double angle_tolerance_rad = 1e-9;              // slack of the end-stop comparison
};

// Steering and drive references d_ref, w_ref (docs/model.md §5).
struct WheelCommands {
  std::array<double, kNumLegs> steer_rad{};          // d_j, + = heading turned left
  std::array<double, kNumLegs> wheel_speed_radps{};  // dz_j/dt, + = rolling forward
  std::array<bool, kNumLegs> flipped{};              // heading turned by pi from nominal
};

// Throws std::invalid_argument when the command needs a heading beyond the
// end-stop that the flip cannot (or may not) serve, or when a hold angle is
// beyond it. In car-like mode the rear wheels are not steered: d = 0 always
// (their nominal heading may be pi, which is d = 0 rolling backward).
WheelCommands wheel_commands(const DriveKinematics& kinematics, const DriveCommand& command,
                             const WheelCommandOptions& options = {});
WheelCommands wheel_commands(const DriveKinematics& kinematics, DriveMode mode,
                             const BodyVelocityCommand& command,
                             const WheelCommandOptions& options = {});

// One piece of a time-varying command: from start_time_s on (until the next
// segment starts), drive `command` in `mode`.
struct DriveCommandSegment {
  double start_time_s = 0.0;
  DriveMode mode = DriveMode::kGeneralAckermann;
  BodyVelocityCommand command;
};

struct DriveScheduleOptions {
  // At each segment start after the first, the body velocity moves from the
  // previous segment's command to the new one over ramp_time_s along the cubic
  // smoothstep s = a^2 (3 - 2a), a = (t - start) / ramp (zero slope at both
  // ends, so the wheel accelerations stay bounded and continuous in time, no
  // torque spike). During the ramp the blended body velocity is served in the
  // segment's mode when both segments share it (every mode's set of
  // representable velocities is a linear space, so the blend stays in it),
  // otherwise in general Ackermann, which serves any blend without scrub.
  // ramp_time_s = 0: piecewise constant (steps).
  double ramp_time_s = 0.0;
  WheelCommandOptions wheel;
};

// Checks a schedule once (e.g. when a scenario is loaded): non-empty, start
// times finite and strictly increasing, each segment at least ramp_time_s
// long (so every ramp starts from a steady command) and every segment's
// command servable in its mode. Throws std::invalid_argument naming the segment.
void validate_drive_schedule(const DriveKinematics& kinematics,
                             const std::vector<DriveCommandSegment>& segments,
                             const DriveScheduleOptions& options = {});

// The wheel commands at time t. Throws std::invalid_argument before the first
// segment's start and for an ill-formed schedule (cheap checks only; call
// validate_drive_schedule once up front for the full check).
WheelCommands wheel_commands_at(const DriveKinematics& kinematics,
                                const std::vector<DriveCommandSegment>& segments, double t_s,
                                const DriveScheduleOptions& options = {});

// A schedule compiled once against one rover's drive kinematics, for the
// right-hand side: the steady wheel commands of every segment are computed up
// front, and every ramp is checked at kRampChecks + 1 evenly spaced blend
// fractions (its commands there are kept). Looking up the commands at a time
// then allocates nothing and throws nothing:
//   * before the first segment's start: the first segment's commands;
//   * in a steady stretch: the stored commands of its segment;
//   * in a ramp: the commands of the blended body velocity, computed as
//     wheel_commands_at() computes them (bit-identical); should a blend
//     between two checked fractions not be servable (a heading crossing the
//     end-stop between them), the commands of the nearest checked fraction.
class CompiledDriveSchedule {
 public:
  static constexpr int kRampChecks = 64;

  // Checks the schedule as validate_drive_schedule() does, and every ramp at
  // the checked fractions; throws std::invalid_argument naming the segment.
  CompiledDriveSchedule(const DriveKinematics& kinematics, std::vector<DriveCommandSegment> segments,
                        const DriveScheduleOptions& options = {});

  WheelCommands at(double t_s) const noexcept;

  const std::vector<DriveCommandSegment>& segments() const { return segments_; }

 private:
  WheelCommands ramp_commands(std::size_t index, double blend_fraction) const;

  DriveKinematics kinematics_;
  std::vector<DriveCommandSegment> segments_;
  DriveScheduleOptions options_;
  std::vector<double> start_times_s_;
  std::vector<WheelCommands> steady_;  // per segment
  // Per segment i > 0 with a ramp: the commands at blend fractions k / kRampChecks.
  std::vector<std::array<WheelCommands, kRampChecks + 1>> ramp_checks_;
};

}  // namespace rover
