// Driving modes: motion commands -> steering angles and wheel speeds
// (paper section 2.1; docs/model.md §1–3 and 5). See drive_kinematics.hpp.
#include "core/drive_kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace rover {
namespace {

constexpr double kPi = std::numbers::pi;

bool is_rear(int leg) { return leg_sign_x(leg) < 0.0; }

// z x r: the velocity of point r under a unit positive yaw rate about the origin.
Vec2 perp(const Vec2& r) { return {-r.y(), r.x()}; }

std::string angle_text(double rad) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << rad * 180.0 / kPi << " deg (" << std::setprecision(4)
    << rad << " rad)";
  return s.str();
}

std::string body_text(const BodyVelocityCommand& c) {
  std::ostringstream s;
  s << "(v_x " << c.forward_mps << " m/s, v_y " << c.lateral_mps << " m/s, yaw rate "
    << c.yaw_rate_radps << " rad/s)";
  return s.str();
}

[[noreturn]] void reject(DriveMode mode, const std::string& why) {
  throw std::invalid_argument(std::string(drive_mode_name(mode)) + " mode: " + why);
}

void require_finite(DriveMode mode, const char* what, double value) {
  if (!std::isfinite(value)) {
    std::ostringstream s;
    s << what << " must be finite, got " << value;
    reject(mode, s.str());
  }
}

void validate(const DriveKinematics& k) {
  if (!(k.wheel_radius_m > 0.0) || !std::isfinite(k.wheel_radius_m)) {
    throw std::invalid_argument("drive kinematics: wheel radius must be positive, got " +
                                std::to_string(k.wheel_radius_m) + " m");
  }
  if (!(k.steering_limit_rad > 0.0)) {
    throw std::invalid_argument("drive kinematics: steering limit must be positive, got " +
                                std::to_string(k.steering_limit_rad) + " rad");
  }
  for (int leg = 0; leg < kNumLegs; ++leg) {
    if (!k.wheel_centre_m[leg].allFinite()) {
      throw std::invalid_argument(std::string("drive kinematics: wheel centre of ") +
                                  kWheelNames[leg] + " is not finite");
    }
  }
}

PlanarMotion translation(double heading_rad, double speed_mps) {
  PlanarMotion m;
  m.kind = PlanarMotion::Kind::kTranslation;
  m.heading_rad = heading_rad;
  m.speed_mps = speed_mps;
  return m;
}

PlanarMotion rotation(const Vec2& icr_m, double positive_sense, double yaw_rate_radps) {
  PlanarMotion m;
  m.kind = PlanarMotion::Kind::kRotation;
  m.icr_m = icr_m;
  m.positive_sense = positive_sense;
  m.yaw_rate_radps = yaw_rate_radps;
  return m;
}

// The yaw-rate sign for which `point` moves forward; if it moves purely
// sideways, left; if it is the ICR, +1. (v_point = omega (d_y, -d_x), d = icr - point.)
double positive_sense(const Vec2& icr_m, const Vec2& point_m) {
  const Vec2 d = icr_m - point_m;
  if (d.y() != 0.0) return d.y() > 0.0 ? 1.0 : -1.0;
  if (d.x() != 0.0) return d.x() < 0.0 ? 1.0 : -1.0;
  return 1.0;
}

// Translation with velocity (v_x, v_y); positive sense forward, else left.
PlanarMotion forward_translation(double v_x, double v_y) {
  if (v_x == 0.0 && v_y == 0.0) return PlanarMotion{};
  const double s = (v_x > 0.0 || (v_x == 0.0 && v_y > 0.0)) ? 1.0 : -1.0;
  return translation(std::atan2(s * v_y, s * v_x), s * std::hypot(v_x, v_y));
}

// Ackermann modes: the ICR on the lateral line through `reference`.
PlanarMotion ackermann_motion(DriveMode mode, const Vec2& reference, double speed_mps,
                              double turn_radius_m) {
  require_finite(mode, "speed", speed_mps);
  if (std::isnan(turn_radius_m)) reject(mode, "turning radius must not be NaN");
  if (std::isinf(turn_radius_m)) return translation(0.0, speed_mps);
  if (turn_radius_m == 0.0) {
    if (speed_mps != 0.0) {
      reject(mode, "a zero turning radius at nonzero speed is a rotation about the reference "
                   "point; use the in-place rotation mode or a body velocity command");
    }
    return rotation(reference, 1.0, 0.0);
  }
  const double sense = turn_radius_m > 0.0 ? 1.0 : -1.0;
  return rotation(reference + Vec2(0.0, turn_radius_m), sense, speed_mps / turn_radius_m);
}

// Ackermann modes from a body command whose ICR is already known to lie on
// the lateral line through `reference` (the command is projected onto it).
PlanarMotion ackermann_motion_from_body(const Vec2& reference, const BodyVelocityCommand& c) {
  const double forward_at_reference = c.forward_mps - c.yaw_rate_radps * reference.y();
  if (c.yaw_rate_radps == 0.0) {
    return forward_at_reference == 0.0 ? PlanarMotion{} : translation(0.0, forward_at_reference);
  }
  const double radius = forward_at_reference / c.yaw_rate_radps;
  if (!std::isfinite(radius)) return translation(0.0, forward_at_reference);
  const Vec2 icr = reference + Vec2(0.0, radius);
  return rotation(icr, positive_sense(icr, reference), c.yaw_rate_radps);
}

void require_small(DriveMode mode, const BodyVelocityCommand& c, double value, double tolerance,
                   const char* what) {
  if (std::abs(value) > tolerance) {
    std::ostringstream s;
    s << "cannot serve the body velocity " << body_text(c) << ": " << what << " is " << value
      << ", not zero (tolerance " << tolerance << ")";
    reject(mode, s.str());
  }
}

struct WheelState {
  bool free = true;  // no line of rolling: rest, or the wheel at the ICR
  Vec2 direction = Vec2::UnitX();  // nominal heading (unit)
  double ground_speed_mps = 0.0;   // signed, along `direction`
};

WheelState wheel_state(const PlanarMotion& m, const Vec2& r_j, double position_tolerance_m) {
  WheelState w;
  switch (m.kind) {
    case PlanarMotion::Kind::kRest:
      break;
    case PlanarMotion::Kind::kTranslation:
      w.free = false;
      w.direction = Vec2(std::cos(m.heading_rad), std::sin(m.heading_rad));
      w.ground_speed_mps = m.speed_mps;
      break;
    case PlanarMotion::Kind::kRotation: {
      const Vec2 d = r_j - m.icr_m;
      const double rho = std::hypot(d.x(), d.y());  // no overflow for a far ICR
      if (rho <= position_tolerance_m) break;
      w.free = false;
      w.direction = m.positive_sense * perp(d) / rho;
      w.ground_speed_mps = m.positive_sense * m.yaw_rate_radps * rho;
      break;
    }
  }
  return w;
}

std::string limit_text(const DriveKinematics& k) {
  return "the end-stop at +-" + angle_text(k.steering_limit_rad);
}

}  // namespace

std::string_view drive_mode_name(DriveMode mode) {
  switch (mode) {
    case DriveMode::kCarLike: return "car-like";
    case DriveMode::kSymmetricAckermann: return "symmetric Ackermann";
    case DriveMode::kGeneralAckermann: return "general Ackermann";
    case DriveMode::kParallel: return "parallel";
    case DriveMode::kLateral: return "lateral";
    case DriveMode::kInPlaceRotation: return "in-place rotation";
  }
  return "unknown";
}

std::string_view drive_mode_keyword(DriveMode mode) {
  switch (mode) {
    case DriveMode::kCarLike: return "car";
    case DriveMode::kSymmetricAckermann: return "ackermann";
    case DriveMode::kGeneralAckermann: return "general-ackermann";
    case DriveMode::kParallel: return "parallel";
    case DriveMode::kLateral: return "lateral";
    case DriveMode::kInPlaceRotation: return "rotation";
  }
  return "unknown";
}

std::optional<DriveMode> drive_mode_from_keyword(std::string_view keyword) {
  for (const DriveMode mode : kAllDriveModes) {
    if (drive_mode_keyword(mode) == keyword) return mode;
  }
  return std::nullopt;
}

DriveKinematics make_drive_kinematics(const RoverParameters& p) {
  DriveKinematics k;
  const RoverGeometry& g = p.geometry;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const double s_x = leg_sign_x(leg), s_y = leg_sign_y(leg);
    // As in the kinematic tree: the bogie pivot is per side (mirrored in y
    // only), hip, knee and wheel-centre offsets per leg.
    const Vec3 centre = mirrored_position(g.bogie_pivot_m, 1.0, s_y) +
                        mirrored_position(g.hip_m + g.knee_m + g.wheel_centre_m, s_x, s_y);
    k.wheel_centre_m[leg] = centre.head<2>();
  }
  k.wheel_radius_m = g.wheel_radius_m;
  k.steering_limit_rad = p.steering.limit_rad;
  validate(k);
  return k;
}

Vec2 rear_axle_centre_m(const DriveKinematics& k) {
  return 0.5 * (k.wheel_centre_m[2] + k.wheel_centre_m[3]);
}

Vec2 axle_midpoint_centre_m(const DriveKinematics& k) {
  const Vec2 front = 0.5 * (k.wheel_centre_m[0] + k.wheel_centre_m[1]);
  return 0.5 * (front + rear_axle_centre_m(k));
}

BodyVelocityCommand body_velocity(const PlanarMotion& m) {
  switch (m.kind) {
    case PlanarMotion::Kind::kRest:
      return {};
    case PlanarMotion::Kind::kTranslation:
      return {m.speed_mps * std::cos(m.heading_rad), m.speed_mps * std::sin(m.heading_rad), 0.0};
    case PlanarMotion::Kind::kRotation: {
      // v_G = omega z x (G - icr); "+ 0.0" turns -0 into 0 for printing.
      const Vec2 v_G = m.yaw_rate_radps * perp(-m.icr_m);
      return {v_G.x() + 0.0, v_G.y() + 0.0, m.yaw_rate_radps};
    }
  }
  return {};
}

DriveCommand car_like_command(const DriveKinematics& k, double speed_mps, double turn_radius_m) {
  const DriveMode mode = DriveMode::kCarLike;
  return {mode, ackermann_motion(mode, rear_axle_centre_m(k), speed_mps, turn_radius_m)};
}

DriveCommand symmetric_ackermann_command(const DriveKinematics& k, double speed_mps,
                                         double turn_radius_m) {
  const DriveMode mode = DriveMode::kSymmetricAckermann;
  return {mode, ackermann_motion(mode, axle_midpoint_centre_m(k), speed_mps, turn_radius_m)};
}

DriveCommand general_ackermann_command(double speed_mps, const Vec2& icr_m) {
  const DriveMode mode = DriveMode::kGeneralAckermann;
  require_finite(mode, "speed", speed_mps);
  if (!icr_m.allFinite()) {
    reject(mode, "the ICR must be finite (drive straight with the parallel mode)");
  }
  if (icr_m.isZero(0.0)) {
    reject(mode, "the ICR is G, where the speed of G is zero; use the in-place rotation mode");
  }
  const double sense = positive_sense(icr_m, Vec2::Zero());
  return {mode, rotation(icr_m, sense, sense * speed_mps / icr_m.norm())};
}

DriveCommand parallel_command(double speed_mps, double crab_angle_rad) {
  const DriveMode mode = DriveMode::kParallel;
  require_finite(mode, "speed", speed_mps);
  require_finite(mode, "crab angle", crab_angle_rad);
  return {mode, translation(crab_angle_rad, speed_mps)};
}

DriveCommand lateral_command(double speed_mps) {
  require_finite(DriveMode::kLateral, "speed", speed_mps);
  return {DriveMode::kLateral, translation(0.5 * kPi, speed_mps)};
}

DriveCommand in_place_rotation_command(double yaw_rate_radps) {
  require_finite(DriveMode::kInPlaceRotation, "yaw rate", yaw_rate_radps);
  return {DriveMode::kInPlaceRotation, rotation(Vec2::Zero(), 1.0, yaw_rate_radps)};
}

DriveCommand drive_command(const DriveKinematics& k, DriveMode mode,
                           const BodyVelocityCommand& c, double tolerance_mps) {
  require_finite(mode, "forward speed", c.forward_mps);
  require_finite(mode, "lateral speed", c.lateral_mps);
  require_finite(mode, "yaw rate", c.yaw_rate_radps);
  switch (mode) {
    case DriveMode::kCarLike: {
      const Vec2 p = rear_axle_centre_m(k);
      require_small(mode, c, c.lateral_mps + c.yaw_rate_radps * p.x(), tolerance_mps,
                    "the rear wheels do not steer, so the rear-axle centre must move straight "
                    "ahead, but its lateral velocity v_y + omega x_rear [m/s]");
      return {mode, ackermann_motion_from_body(p, c)};
    }
    case DriveMode::kSymmetricAckermann: {
      const Vec2 p = axle_midpoint_centre_m(k);
      require_small(mode, c, c.lateral_mps + c.yaw_rate_radps * p.x(), tolerance_mps,
                    "the ICR must lie on the lateral line midway between the axles (use "
                    "general-ackermann for any ICR), but the lateral velocity there, "
                    "v_y + omega x_mid [m/s],");
      return {mode, ackermann_motion_from_body(p, c)};
    }
    case DriveMode::kGeneralAckermann: {
      const double omega = c.yaw_rate_radps;
      if (omega != 0.0) {
        const Vec2 icr(-c.lateral_mps / omega, c.forward_mps / omega);
        if (icr.allFinite()) {
          return {mode, rotation(icr, positive_sense(icr, Vec2::Zero()), omega)};
        }
      }
      return {mode, forward_translation(c.forward_mps, c.lateral_mps)};
    }
    case DriveMode::kParallel:
      require_small(mode, c, c.yaw_rate_radps * 1.0, tolerance_mps,
                    "the wheels stay parallel, so the chassis cannot turn (use general-ackermann), "
                    "but the yaw rate times 1 m [m/s]");
      return {mode, forward_translation(c.forward_mps, c.lateral_mps)};
    case DriveMode::kLateral:
      require_small(mode, c, c.yaw_rate_radps * 1.0, tolerance_mps,
                    "the chassis moves sideways only (use parallel or general-ackermann), but the "
                    "yaw rate times 1 m [m/s]");
      require_small(mode, c, c.forward_mps, tolerance_mps,
                    "the chassis moves sideways only (use parallel for a crab motion), but the "
                    "forward speed [m/s]");
      return lateral_command(c.lateral_mps);
    case DriveMode::kInPlaceRotation:
      require_small(mode, c, std::hypot(c.forward_mps, c.lateral_mps), tolerance_mps,
                    "the chassis turns about G only (use general-ackermann for another ICR), but "
                    "the speed of G [m/s]");
      return in_place_rotation_command(c.yaw_rate_radps);
  }
  reject(mode, "unknown mode");
}

WheelCommands wheel_commands(const DriveKinematics& k, const DriveCommand& command,
                             const WheelCommandOptions& options) {
  validate(k);
  const double limit = k.steering_limit_rad + options.angle_tolerance_rad;
  WheelCommands out;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const WheelState w = wheel_state(command.motion, k.wheel_centre_m[leg], options.position_tolerance_m);
    if (command.mode == DriveMode::kCarLike && is_rear(leg)) {
      // Unsteered: d = 0; the line of rolling must be the x axis.
      if (!w.free) {
        const Vec2 v = w.ground_speed_mps * w.direction;
        if (std::abs(v.y()) > options.velocity_tolerance_mps) {
          std::ostringstream s;
          s << "the rear wheel " << kWheelNames[leg] << " does not steer but would move sideways at "
            << v.y() << " m/s (the ICR must lie on the rear-axle line)";
          reject(command.mode, s.str());
        }
        out.wheel_speed_radps[leg] = v.x() / k.wheel_radius_m;
        out.flipped[leg] = w.direction.x() < 0.0;
      }
      continue;
    }
    if (w.free) {
      const double hold = options.hold_steer_rad[leg];
      if (!(std::abs(hold) <= limit)) {
        reject(command.mode, std::string("wheel ") + kWheelNames[leg] + " has no line of rolling "
                             "and should hold " + angle_text(hold) + ", beyond " + limit_text(k));
      }
      out.steer_rad[leg] = hold;
      continue;
    }
    const double nominal = std::atan2(w.direction.y(), w.direction.x());
    if (std::abs(nominal) <= limit) {
      out.steer_rad[leg] = nominal;
      out.wheel_speed_radps[leg] = w.ground_speed_mps / k.wheel_radius_m;
      continue;
    }
    const double flipped = nominal > 0.0 ? nominal - kPi : nominal + kPi;
    if (options.allow_flip && std::abs(flipped) <= limit) {
      out.steer_rad[leg] = flipped;
      out.wheel_speed_radps[leg] = -w.ground_speed_mps / k.wheel_radius_m;
      out.flipped[leg] = true;
      continue;
    }
    std::string why = std::string("wheel ") + kWheelNames[leg] + " needs a steering angle of " +
                      angle_text(nominal) + ", beyond " + limit_text(k) + "; ";
    if (std::abs(flipped) > limit) {
      why += "the flipped heading " + angle_text(flipped) + " is beyond it too";
    } else {
      why += "flipping it to " + angle_text(flipped) +
             " with the speed reversed is disabled (allow_flip = false)";
    }
    reject(command.mode, why + "; body velocity " + body_text(body_velocity(command.motion)));
  }
  return out;
}

WheelCommands wheel_commands(const DriveKinematics& k, DriveMode mode,
                             const BodyVelocityCommand& command,
                             const WheelCommandOptions& options) {
  return wheel_commands(k, drive_command(k, mode, command, options.velocity_tolerance_mps), options);
}

namespace {

void check_schedule_shape(const std::vector<DriveCommandSegment>& segments, double ramp_time_s) {
  if (!(ramp_time_s >= 0.0) || !std::isfinite(ramp_time_s)) {
    throw std::invalid_argument("drive schedule: ramp time must be finite and >= 0, got " +
                                std::to_string(ramp_time_s) + " s");
  }
  if (segments.empty()) throw std::invalid_argument("drive schedule: no segments");
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (!std::isfinite(segments[i].start_time_s)) {
      throw std::invalid_argument("drive schedule: segment " + std::to_string(i) +
                                  " has a non-finite start time");
    }
    if (i > 0) {
      const double duration = segments[i].start_time_s - segments[i - 1].start_time_s;
      if (!(duration > 0.0)) {
        throw std::invalid_argument("drive schedule: segment " + std::to_string(i) + " starts at " +
                                    std::to_string(segments[i].start_time_s) +
                                    " s, not after segment " + std::to_string(i - 1) + " (" +
                                    std::to_string(segments[i - 1].start_time_s) + " s)");
      }
      if (duration < ramp_time_s && i > 1) {
        throw std::invalid_argument("drive schedule: segment " + std::to_string(i - 1) + " lasts " +
                                    std::to_string(duration) + " s, shorter than the ramp time " +
                                    std::to_string(ramp_time_s) + " s");
      }
    }
  }
}

// The commands at blend fraction a in [0, 1) of the ramp from segment `from`
// into segment `to` (DriveScheduleOptions); `options` hold the steering of
// `from`.
WheelCommands ramp_wheel_commands(const DriveKinematics& k, const DriveCommandSegment& from_segment,
                                  const DriveCommandSegment& to_segment, double a,
                                  const WheelCommandOptions& options) {
  const BodyVelocityCommand& from = from_segment.command;
  const BodyVelocityCommand& to = to_segment.command;
  const double s = a * a * (3.0 - 2.0 * a);
  const BodyVelocityCommand blend{from.forward_mps + s * (to.forward_mps - from.forward_mps),
                                  from.lateral_mps + s * (to.lateral_mps - from.lateral_mps),
                                  from.yaw_rate_radps + s * (to.yaw_rate_radps - from.yaw_rate_radps)};
  const DriveMode mode =
      from_segment.mode == to_segment.mode ? to_segment.mode : DriveMode::kGeneralAckermann;
  return wheel_commands(k, mode, blend, options);
}

// Steady wheel commands of segments 0..last; a wheel with a free heading holds
// where the previous segment left it.
WheelCommands steady_commands(const DriveKinematics& k,
                              const std::vector<DriveCommandSegment>& segments, std::size_t last,
                              WheelCommandOptions options, std::array<double, kNumLegs>* hold_in) {
  WheelCommands out;
  for (std::size_t i = 0; i <= last; ++i) {
    if (hold_in != nullptr && i == last) *hold_in = options.hold_steer_rad;
    try {
      out = wheel_commands(k, segments[i].mode, segments[i].command, options);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("drive schedule segment " + std::to_string(i) + " (from " +
                                  std::to_string(segments[i].start_time_s) + " s): " + e.what());
    }
    options.hold_steer_rad = out.steer_rad;
  }
  return out;
}

}  // namespace

void validate_drive_schedule(const DriveKinematics& k,
                             const std::vector<DriveCommandSegment>& segments,
                             const DriveScheduleOptions& options) {
  check_schedule_shape(segments, options.ramp_time_s);
  steady_commands(k, segments, segments.size() - 1, options.wheel, nullptr);
}

WheelCommands wheel_commands_at(const DriveKinematics& k,
                                const std::vector<DriveCommandSegment>& segments, double t_s,
                                const DriveScheduleOptions& options) {
  check_schedule_shape(segments, options.ramp_time_s);
  if (!(t_s >= segments.front().start_time_s)) {
    throw std::invalid_argument("drive schedule: t = " + std::to_string(t_s) +
                                " s is before the first segment (starts at " +
                                std::to_string(segments.front().start_time_s) + " s)");
  }
  const auto after = std::upper_bound(
      segments.begin(), segments.end(), t_s,
      [](double t, const DriveCommandSegment& s) { return t < s.start_time_s; });
  const std::size_t index = static_cast<std::size_t>(after - segments.begin()) - 1;
  const DriveCommandSegment& current = segments[index];
  const double since_start_s = t_s - current.start_time_s;
  std::array<double, kNumLegs> hold{};
  const WheelCommands steady = steady_commands(k, segments, index, options.wheel, &hold);
  if (index == 0 || since_start_s >= options.ramp_time_s) return steady;

  WheelCommandOptions ramp_options = options.wheel;
  ramp_options.hold_steer_rad = hold;
  try {
    return ramp_wheel_commands(k, segments[index - 1], current, since_start_s / options.ramp_time_s,
                               ramp_options);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("drive schedule: ramp into segment " + std::to_string(index) +
                                " at t = " + std::to_string(t_s) + " s: " + e.what());
  }
}

CompiledDriveSchedule::CompiledDriveSchedule(const DriveKinematics& kinematics,
                                             std::vector<DriveCommandSegment> segments,
                                             const DriveScheduleOptions& options)
    : kinematics_(kinematics), segments_(std::move(segments)), options_(options) {
  check_schedule_shape(segments_, options_.ramp_time_s);
  const std::size_t n = segments_.size();
  WheelCommandOptions wheel = options_.wheel;
  for (std::size_t i = 0; i < n; ++i) {
    start_times_s_.push_back(segments_[i].start_time_s);
    try {
      steady_.push_back(wheel_commands(kinematics_, segments_[i].mode, segments_[i].command, wheel));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("drive schedule segment " + std::to_string(i) + " (from " +
                                  std::to_string(segments_[i].start_time_s) + " s): " + e.what());
    }
    wheel.hold_steer_rad = steady_.back().steer_rad;
  }
  if (options_.ramp_time_s > 0.0) {
    ramp_checks_.resize(n);
    for (std::size_t i = 1; i < n; ++i)
      for (int c = 0; c <= kRampChecks; ++c) {
        const double a = static_cast<double>(c) / kRampChecks;
        try {
          ramp_checks_[i][static_cast<std::size_t>(c)] = ramp_commands(i, a);
        } catch (const std::invalid_argument& e) {
          throw std::invalid_argument("drive schedule: ramp into segment " + std::to_string(i) +
                                      " at " + std::to_string(segments_[i].start_time_s + a * options_.ramp_time_s) +
                                      " s: " + e.what());
        }
      }
  }
}

WheelCommands CompiledDriveSchedule::ramp_commands(std::size_t index, double blend_fraction) const {
  WheelCommandOptions ramp_options = options_.wheel;
  ramp_options.hold_steer_rad = steady_[index - 1].steer_rad;
  return ramp_wheel_commands(kinematics_, segments_[index - 1], segments_[index], blend_fraction,
                             ramp_options);
}

WheelCommands CompiledDriveSchedule::at(double t_s) const noexcept {
  const auto after = std::upper_bound(start_times_s_.begin(), start_times_s_.end(), t_s);
  if (after == start_times_s_.begin()) return steady_.front();
  const std::size_t index = static_cast<std::size_t>(after - start_times_s_.begin()) - 1;
  const double since_start_s = t_s - start_times_s_[index];
  if (index == 0 || !(since_start_s < options_.ramp_time_s)) return steady_[index];
  const double a = since_start_s / options_.ramp_time_s;
  try {
    return ramp_commands(index, a);
  } catch (...) {
    return ramp_checks_[index][static_cast<std::size_t>(std::lround(a * kRampChecks))];
  }
}

}  // namespace rover
