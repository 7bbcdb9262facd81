// Driving modes (core/drive_kinematics.cpp): every mode's wheel states must be
// one rigid-body motion of the chassis (no wheel scrubs), Ackermann geometry,
// rotation about G, the end-stop behaviour (flip or reject, never clamp) and
// the straight-line limits; the time-varying schedule.
#include "core/drive_kinematics.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/kinematic_tree.hpp"

namespace rover {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTol = 1e-12;
constexpr double kInf = std::numeric_limits<double>::infinity();

const DriveKinematics kKin = make_drive_kinematics(default_rover_parameters());

// v_G + omega z x r: the chassis velocity at r.
Vec2 rigid_velocity(const BodyVelocityCommand& b, const Vec2& r) {
  return {b.forward_mps - b.yaw_rate_radps * r.y(), b.lateral_mps + b.yaw_rate_radps * r.x()};
}

Vec2 heading(double steer_rad) { return {std::cos(steer_rad), std::sin(steer_rad)}; }

// The wheel-centre velocity the wheel's state produces when it rolls without slip.
Vec2 rolling_velocity(const DriveKinematics& k, const WheelCommands& w, int leg) {
  return w.wheel_speed_radps[leg] * k.wheel_radius_m * heading(w.steer_rad[leg]);
}

void expect_no_scrub(const DriveKinematics& k, const WheelCommands& w,
                     const BodyVelocityCommand& body, const std::string& what) {
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec2 expected = rigid_velocity(body, k.wheel_centre_m[leg]);
    const Vec2 actual = rolling_velocity(k, w, leg);
    EXPECT_NEAR(actual.x(), expected.x(), kTol) << what << ", wheel " << kWheelNames[leg];
    EXPECT_NEAR(actual.y(), expected.y(), kTol) << what << ", wheel " << kWheelNames[leg];
    EXPECT_LE(std::abs(w.steer_rad[leg]), k.steering_limit_rad) << what << ", " << kWheelNames[leg];
  }
}

std::string describe(DriveMode mode, const BodyVelocityCommand& b) {
  return std::string(drive_mode_name(mode)) + " (" + std::to_string(b.forward_mps) + ", " +
         std::to_string(b.lateral_mps) + ", " + std::to_string(b.yaw_rate_radps) + ")";
}

// Body commands each mode can represent, built from the geometry (not from
// the code under test): car-like v_y = -omega x_rear, symmetric v_y = -omega x_mid.
std::vector<std::pair<DriveMode, BodyVelocityCommand>> representable_commands() {
  const double x_rear = 0.5 * (kKin.wheel_centre_m[2].x() + kKin.wheel_centre_m[3].x());
  const double x_mid = 0.25 * (kKin.wheel_centre_m[0].x() + kKin.wheel_centre_m[1].x() +
                               kKin.wheel_centre_m[2].x() + kKin.wheel_centre_m[3].x());
  std::vector<std::pair<DriveMode, BodyVelocityCommand>> c;
  for (const double omega : {0.0, 0.5, -0.8, 2.0, 10.0}) {
    for (const double v_x : {0.5, -0.3, 0.0}) {
      c.push_back({DriveMode::kCarLike, {v_x, -omega * x_rear, omega}});
      c.push_back({DriveMode::kSymmetricAckermann, {v_x, -omega * x_mid, omega}});
      c.push_back({DriveMode::kGeneralAckermann, {v_x, 0.2, omega}});
      c.push_back({DriveMode::kGeneralAckermann, {v_x, -0.4, omega}});
    }
    c.push_back({DriveMode::kInPlaceRotation, {0.0, 0.0, omega}});
  }
  for (const double v_y : {0.3, -0.2, 0.0}) {
    c.push_back({DriveMode::kLateral, {0.0, v_y, 0.0}});
    for (const double v_x : {0.4, -0.25, 0.0}) c.push_back({DriveMode::kParallel, {v_x, v_y, 0.0}});
  }
  return c;
}

TEST(DriveKinematics, WheelCentresFollowModelGeometryAndKinematicTree) {
  const KinematicTree tree = build_kinematic_tree(default_rover_parameters());
  const TreeKinematics at_zero =
      forward_kinematics(tree, Coordinates::Zero(), Coordinates::Zero());
  for (int leg = 0; leg < kNumLegs; ++leg) {
    EXPECT_NEAR(kKin.wheel_centre_m[leg].x(), leg_sign_x(leg) * 0.360, kTol);   // docs/model.md §3
    EXPECT_NEAR(kKin.wheel_centre_m[leg].y(), leg_sign_y(leg) * 0.2215, kTol);
    const Vec3 hub = at_zero.nodes[node::hub(leg)].origin;  // the steering axis
    EXPECT_NEAR(kKin.wheel_centre_m[leg].x(), hub.x(), kTol);
    EXPECT_NEAR(kKin.wheel_centre_m[leg].y(), hub.y(), kTol);
  }
  EXPECT_EQ(kKin.wheel_radius_m, 0.085);
  EXPECT_EQ(kKin.steering_limit_rad, 1.7453);

  RoverParameters p = default_rover_parameters();
  p.geometry.wheel_radius_m = 0.0;
  EXPECT_THROW(make_drive_kinematics(p), std::invalid_argument);
}

TEST(DriveKinematics, EveryModeRollsWithoutScrubForBodyCommands) {
  for (const auto& [mode, body] : representable_commands()) {
    const std::string what = describe(mode, body);
    const DriveCommand command = drive_command(kKin, mode, body);
    const BodyVelocityCommand served = body_velocity(command.motion);
    EXPECT_NEAR(served.forward_mps, body.forward_mps, kTol) << what;
    EXPECT_NEAR(served.lateral_mps, body.lateral_mps, kTol) << what;
    EXPECT_NEAR(served.yaw_rate_radps, body.yaw_rate_radps, kTol) << what;
    expect_no_scrub(kKin, wheel_commands(kKin, mode, body), body, what);
  }
}

TEST(DriveKinematics, EveryModeRollsWithoutScrubForNaturalParameters) {
  std::vector<DriveCommand> commands;
  for (const double v : {0.5, -0.4}) {
    for (const double radius : {1.0, -0.7, 0.3, 0.2, -0.1, 0.05, 4.0}) {
      commands.push_back(car_like_command(kKin, v, radius));
      commands.push_back(symmetric_ackermann_command(kKin, v, radius));
    }
    for (const Vec2& icr : {Vec2(0.5, 1.0), Vec2(-0.2, -0.3), Vec2(1.0, 0.0), Vec2(0.0, -0.05)})
      commands.push_back(general_ackermann_command(v, icr));
    for (const double crab : {0.0, 0.4, -1.2, 2.5, -kPi}) commands.push_back(parallel_command(v, crab));
    commands.push_back(lateral_command(v));
    commands.push_back(in_place_rotation_command(v));
  }
  for (const DriveCommand& c : commands) {
    const BodyVelocityCommand body = body_velocity(c.motion);
    const std::string what = describe(c.mode, body);
    expect_no_scrub(kKin, wheel_commands(kKin, c), body, what);
    // The same motion as a body command gives the same wheel states.
    const WheelCommands a = wheel_commands(kKin, c);
    const WheelCommands b = wheel_commands(kKin, c.mode, body);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      EXPECT_NEAR(a.steer_rad[leg], b.steer_rad[leg], 1e-9) << what << " " << kWheelNames[leg];
      EXPECT_NEAR(a.wheel_speed_radps[leg], b.wheel_speed_radps[leg], 1e-9) << what;
    }
  }
}

TEST(DriveKinematics, NaturalParametersMeanWhatTheySay) {
  // Symmetric Ackermann, speed v and radius R about G: omega = v / R, v_G = (v, 0).
  const BodyVelocityCommand ack = body_velocity(symmetric_ackermann_command(kKin, 0.5, 2.0).motion);
  EXPECT_NEAR(ack.forward_mps, 0.5, kTol);
  EXPECT_NEAR(ack.lateral_mps, 0.0, kTol);
  EXPECT_NEAR(ack.yaw_rate_radps, 0.25, kTol);
  // Car-like: the rear-axle centre (-0.36, 0) moves at (v, 0) about (-0.36, R).
  const BodyVelocityCommand car = body_velocity(car_like_command(kKin, -0.6, -1.5).motion);
  const Vec2 rear = rigid_velocity(car, Vec2(-0.360, 0.0));
  EXPECT_NEAR(rear.x(), -0.6, kTol);
  EXPECT_NEAR(rear.y(), 0.0, kTol);
  EXPECT_NEAR(car.yaw_rate_radps, 0.4, kTol);
  // General Ackermann: the ICR is at rest, G moves forward with |v_G| = |v|.
  const Vec2 icr(0.4, -0.8);
  const BodyVelocityCommand gen = body_velocity(general_ackermann_command(0.3, icr).motion);
  EXPECT_NEAR(rigid_velocity(gen, icr).norm(), 0.0, kTol);
  EXPECT_NEAR(std::hypot(gen.forward_mps, gen.lateral_mps), 0.3, kTol);
  EXPECT_GT(gen.forward_mps, 0.0);
  // Parallel and lateral.
  const BodyVelocityCommand crab = body_velocity(parallel_command(0.3, 0.5).motion);
  EXPECT_NEAR(crab.forward_mps, 0.3 * std::cos(0.5), kTol);
  EXPECT_NEAR(crab.lateral_mps, 0.3 * std::sin(0.5), kTol);
  const WheelCommands side = wheel_commands(kKin, lateral_command(-0.2));
  for (int leg = 0; leg < kNumLegs; ++leg) {
    EXPECT_NEAR(side.steer_rad[leg], kPi / 2, kTol);
    EXPECT_NEAR(side.wheel_speed_radps[leg], -0.2 / 0.085, kTol);
  }
}

TEST(DriveKinematics, InPlaceRotationTurnsAboutG) {
  for (const double omega : {0.7, -1.3}) {
    const DriveCommand c = in_place_rotation_command(omega);
    const BodyVelocityCommand body = body_velocity(c.motion);
    EXPECT_EQ(body.forward_mps, 0.0);
    EXPECT_EQ(body.lateral_mps, 0.0);
    const WheelCommands w = wheel_commands(kKin, c);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      const Vec2 r = kKin.wheel_centre_m[leg];
      const Vec2 v = rolling_velocity(kKin, w, leg);
      EXPECT_NEAR(v.dot(r), 0.0, kTol) << kWheelNames[leg];  // tangent to the circle about G
      EXPECT_NEAR(v.norm(), std::abs(omega) * r.norm(), kTol);
      EXPECT_NEAR(r.x() * v.y() - r.y() * v.x(), omega * r.squaredNorm(), kTol);  // sense
      // The symmetric "diamond": every wheel at +-atan(x / y) of its own centre.
      EXPECT_NEAR(std::abs(w.steer_rad[leg]), std::atan(0.360 / 0.2215), kTol);
    }
  }
}

TEST(DriveKinematics, AckermannHeadingsArePerpendicularToTheLineFromTheIcr) {
  const Vec2 mid = axle_midpoint_centre_m(kKin), rear = rear_axle_centre_m(kKin);
  for (const double radius : {1.0, -1.0, 0.5, 0.3, 0.2, -0.15, 0.05, 6.0}) {
    for (const bool car : {false, true}) {
      const DriveCommand c = car ? car_like_command(kKin, 0.4, radius)
                                 : symmetric_ackermann_command(kKin, 0.4, radius);
      const Vec2 icr = (car ? rear : mid) + Vec2(0.0, radius);
      const WheelCommands w = wheel_commands(kKin, c);
      for (int leg = 0; leg < kNumLegs; ++leg) {
        const Vec2 from_icr = kKin.wheel_centre_m[leg] - icr;
        EXPECT_NEAR(heading(w.steer_rad[leg]).dot(from_icr), 0.0, kTol)
            << (car ? "car R=" : "ackermann R=") << radius << " " << kWheelNames[leg];
      }
      if (car) {
        EXPECT_EQ(w.steer_rad[2], 0.0);
        EXPECT_EQ(w.steer_rad[3], 0.0);
      } else {  // front and rear steer opposite
        EXPECT_NEAR(w.steer_rad[0], -w.steer_rad[2], kTol);
        EXPECT_NEAR(w.steer_rad[1], -w.steer_rad[3], kTol);
      }
    }
  }
  // Textbook Ackermann angles for a wide turn (R > W/2): tan d = (L/2) / (R -+ W/2)
  // symmetric, tan d = L / (R -+ W/2) car-like, with L = 0.720 m, W = 0.443 m.
  const double radius = 1.2;
  const WheelCommands sym = wheel_commands(kKin, symmetric_ackermann_command(kKin, 0.3, radius));
  EXPECT_NEAR(sym.steer_rad[0], std::atan(0.360 / (radius - 0.2215)), kTol);
  EXPECT_NEAR(sym.steer_rad[1], std::atan(0.360 / (radius + 0.2215)), kTol);
  const WheelCommands car = wheel_commands(kKin, car_like_command(kKin, 0.3, radius));
  EXPECT_NEAR(car.steer_rad[0], std::atan(0.720 / (radius - 0.2215)), kTol);
  EXPECT_NEAR(car.steer_rad[1], std::atan(0.720 / (radius + 0.2215)), kTol);
}

TEST(DriveKinematics, MirroredTurnMirrorsTheWheels) {
  for (const double radius : {0.8, 0.18}) {
    const WheelCommands left = wheel_commands(kKin, symmetric_ackermann_command(kKin, 0.3, radius));
    const WheelCommands right = wheel_commands(kKin, symmetric_ackermann_command(kKin, 0.3, -radius));
    for (const auto& [a, b] : {std::pair{0, 1}, std::pair{2, 3}}) {
      EXPECT_NEAR(left.steer_rad[a], -right.steer_rad[b], kTol);
      EXPECT_NEAR(left.wheel_speed_radps[a], right.wheel_speed_radps[b], kTol);
    }
  }
}

TEST(DriveKinematics, ReversingAndStoppingKeepTheSteering) {
  for (const double radius : {0.9, -0.25, 0.12}) {
    const WheelCommands fwd = wheel_commands(kKin, symmetric_ackermann_command(kKin, 0.4, radius));
    const WheelCommands back = wheel_commands(kKin, symmetric_ackermann_command(kKin, -0.4, radius));
    const WheelCommands stop = wheel_commands(kKin, symmetric_ackermann_command(kKin, 0.0, radius));
    for (int leg = 0; leg < kNumLegs; ++leg) {
      EXPECT_EQ(fwd.steer_rad[leg], back.steer_rad[leg]);
      EXPECT_EQ(fwd.steer_rad[leg], stop.steer_rad[leg]);  // pre-steered at zero speed
      EXPECT_NEAR(fwd.wheel_speed_radps[leg], -back.wheel_speed_radps[leg], kTol);
      EXPECT_EQ(stop.wheel_speed_radps[leg], 0.0);
    }
  }
}

TEST(DriveKinematics, ZeroBodyCommandHoldsOrKeepsTheModesGeometry) {
  WheelCommandOptions options;
  options.hold_steer_rad = {0.1, -0.2, 0.3, -0.4};
  for (const DriveMode mode : {DriveMode::kSymmetricAckermann, DriveMode::kGeneralAckermann,
                               DriveMode::kParallel}) {
    const WheelCommands w = wheel_commands(kKin, mode, BodyVelocityCommand{}, options);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      EXPECT_EQ(w.steer_rad[leg], options.hold_steer_rad[leg]);
      EXPECT_EQ(w.wheel_speed_radps[leg], 0.0);
    }
  }
  const WheelCommands car = wheel_commands(kKin, DriveMode::kCarLike, BodyVelocityCommand{}, options);
  EXPECT_EQ(car.steer_rad[0], 0.1);
  EXPECT_EQ(car.steer_rad[2], 0.0);  // rear wheels never steer in car-like mode
  const WheelCommands lateral = wheel_commands(kKin, DriveMode::kLateral, BodyVelocityCommand{});
  const WheelCommands spin = wheel_commands(kKin, DriveMode::kInPlaceRotation, BodyVelocityCommand{});
  const WheelCommands spin_moving = wheel_commands(kKin, in_place_rotation_command(1.0));
  for (int leg = 0; leg < kNumLegs; ++leg) {
    EXPECT_NEAR(lateral.steer_rad[leg], kPi / 2, kTol);
    EXPECT_EQ(spin.steer_rad[leg], spin_moving.steer_rad[leg]);
    EXPECT_EQ(spin.wheel_speed_radps[leg], 0.0);
  }
  // A wheel at the ICR has no line of rolling: it holds, with zero speed.
  const WheelCommands pivot =
      wheel_commands(kKin, general_ackermann_command(0.3, kKin.wheel_centre_m[1]), options);
  EXPECT_EQ(pivot.steer_rad[1], -0.2);
  EXPECT_EQ(pivot.wheel_speed_radps[1], 0.0);
  expect_no_scrub(kKin, pivot, body_velocity(general_ackermann_command(0.3, kKin.wheel_centre_m[1]).motion),
                  "pivot about FR");
  // A hold angle beyond the end-stop is rejected, not clamped.
  options.hold_steer_rad[0] = 2.0;
  EXPECT_THROW(wheel_commands(kKin, DriveMode::kGeneralAckermann, BodyVelocityCommand{}, options),
               std::invalid_argument);
}

TEST(DriveKinematics, StraightLineIsTheLimitOfLargeRadii) {
  const double v = 0.5;
  std::vector<WheelCommands> straight{
      wheel_commands(kKin, symmetric_ackermann_command(kKin, v, kInf)),
      wheel_commands(kKin, symmetric_ackermann_command(kKin, v, -kInf)),
      wheel_commands(kKin, car_like_command(kKin, v, kInf)),
      wheel_commands(kKin, parallel_command(v, 0.0))};
  for (const DriveMode mode : {DriveMode::kCarLike, DriveMode::kSymmetricAckermann,
                               DriveMode::kGeneralAckermann, DriveMode::kParallel})
    straight.push_back(wheel_commands(kKin, mode, BodyVelocityCommand{v, 0.0, 0.0}));
  for (const WheelCommands& w : straight)
    for (int leg = 0; leg < kNumLegs; ++leg) {
      EXPECT_EQ(w.steer_rad[leg], 0.0);
      EXPECT_NEAR(w.wheel_speed_radps[leg], v / kKin.wheel_radius_m, kTol);
    }
  // Approached from either side, continuously.
  for (const double radius : {1e7, -1e7}) {
    const WheelCommands sym = wheel_commands(kKin, symmetric_ackermann_command(kKin, v, radius));
    const WheelCommands car = wheel_commands(kKin, car_like_command(kKin, v, radius));
    const WheelCommands gen = wheel_commands(kKin, general_ackermann_command(v, Vec2(0.0, radius)));
    for (const WheelCommands* w : {&sym, &car, &gen})
      for (int leg = 0; leg < kNumLegs; ++leg) {
        EXPECT_NEAR(w->steer_rad[leg], 0.0, 1e-6);
        EXPECT_NEAR(w->wheel_speed_radps[leg], v / kKin.wheel_radius_m, 1e-6);
      }
  }
  // A vanishing yaw rate in a body command, down to the underflow of the ICR.
  for (const double omega : {1e-12, 1e-300, 1e-320}) {
    const BodyVelocityCommand b{v, 0.0, omega};
    expect_no_scrub(kKin, wheel_commands(kKin, DriveMode::kGeneralAckermann, b), b, "tiny omega");
  }
}

TEST(DriveKinematics, CommandsAModeCannotRepresentAreRejected) {
  const auto rejects = [](DriveMode mode, BodyVelocityCommand b, const std::string& needle) {
    try {
      wheel_commands(kKin, mode, b);
      ADD_FAILURE() << describe(mode, b) << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(drive_mode_name(mode)), std::string::npos) << e.what();
    }
  };
  rejects(DriveMode::kCarLike, {0.5, 0.1, 0.0}, "rear");
  rejects(DriveMode::kCarLike, {0.5, 0.0, 0.5}, "rear");  // ICR on G's line, not the rear axle
  rejects(DriveMode::kSymmetricAckermann, {0.5, 0.1, 0.5}, "general-ackermann");
  rejects(DriveMode::kParallel, {0.5, 0.0, 0.1}, "yaw rate");
  rejects(DriveMode::kLateral, {0.1, 0.3, 0.0}, "forward");
  rejects(DriveMode::kLateral, {0.0, 0.3, 0.2}, "yaw rate");
  rejects(DriveMode::kInPlaceRotation, {0.1, 0.0, 0.5}, "speed of G");
  // Within the tolerance a command is projected onto the mode, exactly.
  const WheelCommands w = wheel_commands(kKin, DriveMode::kLateral, {1e-12, 0.3, 0.0});
  for (int leg = 0; leg < kNumLegs; ++leg) EXPECT_NEAR(w.steer_rad[leg], kPi / 2, kTol);
  // Natural parameters that mean nothing.
  EXPECT_THROW(symmetric_ackermann_command(kKin, 0.3, 0.0), std::invalid_argument);
  EXPECT_THROW(general_ackermann_command(0.3, Vec2::Zero()), std::invalid_argument);
  EXPECT_THROW(parallel_command(std::nan(""), 0.0), std::invalid_argument);
}

// The heading each wheel needs when it rolls forward in the command's positive
// sense (forward motion): the direction of its rigid-body velocity.
double needed_heading(const BodyVelocityCommand& forward_body, int leg) {
  const Vec2 v = rigid_velocity(forward_body, kKin.wheel_centre_m[leg]);
  return std::atan2(v.y(), v.x());
}

TEST(DriveKinematics, EndStopsRejectOrFlipButNeverClamp) {
  WheelCommandOptions no_flip;
  no_flip.allow_flip = false;
  int rejected = 0, flipped = 0;
  for (double radius = -2.0; radius <= 2.0; radius += 0.01) {
    if (std::abs(radius) < 1e-9) continue;
    for (const bool car : {false, true}) {
      const DriveCommand c = car ? car_like_command(kKin, 0.4, radius)
                                 : symmetric_ackermann_command(kKin, 0.4, radius);
      const BodyVelocityCommand body = body_velocity(c.motion);
      bool beyond = false;
      for (int leg = 0; leg < kNumLegs; ++leg) {
        if (car && leg >= 2) continue;  // unsteered
        beyond = beyond || std::abs(needed_heading(body, leg)) > kKin.steering_limit_rad;
      }
      // Without the flip: served exactly iff no wheel needs a heading past the end-stop.
      if (beyond) {
        EXPECT_THROW(wheel_commands(kKin, c, no_flip), std::invalid_argument) << radius;
        ++rejected;
      } else {
        expect_no_scrub(kKin, wheel_commands(kKin, c, no_flip), body, "no flip");
      }
      // With the flip: always served exactly; flipped wheels roll backward.
      const WheelCommands w = wheel_commands(kKin, c);
      expect_no_scrub(kKin, w, body, "flip R=" + std::to_string(radius));
      for (int leg = 0; leg < kNumLegs; ++leg) {
        if (car && leg >= 2) continue;
        const bool must_flip = std::abs(needed_heading(body, leg)) > kKin.steering_limit_rad;
        EXPECT_EQ(w.flipped[leg], must_flip) << radius << " " << kWheelNames[leg];
        if (w.flipped[leg]) {
          EXPECT_LT(w.wheel_speed_radps[leg], 0.0);
          ++flipped;
        }
      }
    }
  }
  EXPECT_GT(rejected, 10);  // the sweep does reach past the end-stops
  EXPECT_GT(flipped, 10);
}

TEST(DriveKinematics, EndStopMessageNamesWheelAngleAndLimit) {
  // R = 0.1 m about G: FL needs atan2(0.36, 0.1 - 0.2215) = 108.6 deg > 100 deg.
  WheelCommandOptions no_flip;
  no_flip.allow_flip = false;
  try {
    wheel_commands(kKin, symmetric_ackermann_command(kKin, 0.3, 0.1), no_flip);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("symmetric Ackermann"), std::string::npos) << m;
    EXPECT_NE(m.find("FL"), std::string::npos) << m;
    EXPECT_NE(m.find("108.6 deg"), std::string::npos) << m;
    EXPECT_NE(m.find("100.0 deg"), std::string::npos) << m;
    EXPECT_NE(m.find("allow_flip"), std::string::npos) << m;
  }
  // With the flip, FL turns to 108.6 - 180 = -71.4 deg and rolls backward.
  const WheelCommands w = wheel_commands(kKin, symmetric_ackermann_command(kKin, 0.3, 0.1));
  EXPECT_NEAR(w.steer_rad[0], std::atan2(0.360, 0.1 - 0.2215) - kPi, kTol);
  EXPECT_TRUE(w.flipped[0]);
  EXPECT_FALSE(w.flipped[1]);
  // In-place rotation needs the flip on the left wheels (121.6 deg).
  EXPECT_THROW(wheel_commands(kKin, in_place_rotation_command(0.5), no_flip),
               std::invalid_argument);
  // A crab angle of 120 deg is served at -60 deg rolling backward.
  const WheelCommands crab = wheel_commands(kKin, parallel_command(0.2, 2 * kPi / 3));
  for (int leg = 0; leg < kNumLegs; ++leg) {
    EXPECT_NEAR(crab.steer_rad[leg], -kPi / 3, kTol);
    EXPECT_NEAR(crab.wheel_speed_radps[leg], -0.2 / kKin.wheel_radius_m, kTol);
  }
}

TEST(DriveKinematics, LimitBelowNinetyDegreesRejectsWhatNoFlipCanServe) {
  RoverParameters p = default_rover_parameters();
  p.steering.limit_rad = 60.0 * kPi / 180.0;
  const DriveKinematics narrow = make_drive_kinematics(p);
  try {
    wheel_commands(narrow, lateral_command(0.2));
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("beyond it too"), std::string::npos) << e.what();
  }
  EXPECT_THROW(wheel_commands(narrow, parallel_command(0.2, 70.0 * kPi / 180.0)),
               std::invalid_argument);
  EXPECT_NO_THROW(wheel_commands(narrow, parallel_command(0.2, 50.0 * kPi / 180.0)));
  // The diamond of in-place rotation needs 58.4 deg: served.
  expect_no_scrub(narrow, wheel_commands(narrow, in_place_rotation_command(0.5)),
                  {0.0, 0.0, 0.5}, "narrow rotation");
}

TEST(DriveSchedule, PiecewiseConstantWithoutRamp) {
  const std::vector<DriveCommandSegment> plan{
      {0.0, DriveMode::kSymmetricAckermann, {0.5, 0.0, 0.0}},
      {1.0, DriveMode::kSymmetricAckermann, {0.5, 0.0, 0.5}},
      {2.0, DriveMode::kInPlaceRotation, {0.0, 0.0, -0.4}}};
  validate_drive_schedule(kKin, plan);
  for (const double t : {0.0, 0.5, 1.0, 1.7, 2.0, 9.0}) {
    const std::size_t i = t < 1.0 ? 0 : (t < 2.0 ? 1 : 2);
    const WheelCommands w = wheel_commands_at(kKin, plan, t);
    const WheelCommands expected = wheel_commands(kKin, plan[i].mode, plan[i].command);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      EXPECT_EQ(w.steer_rad[leg], expected.steer_rad[leg]) << t;
      EXPECT_EQ(w.wheel_speed_radps[leg], expected.wheel_speed_radps[leg]) << t;
    }
  }
  EXPECT_THROW(wheel_commands_at(kKin, plan, -0.1), std::invalid_argument);
}

TEST(DriveSchedule, RampBlendsSmoothlyWithoutScrub) {
  const std::vector<DriveCommandSegment> plan{
      {0.0, DriveMode::kSymmetricAckermann, {0.5, 0.0, 0.0}},
      {1.0, DriveMode::kSymmetricAckermann, {0.5, 0.0, 1.0}},  // same mode
      {2.0, DriveMode::kLateral, {0.0, 0.3, 0.0}}};            // mode change
  DriveScheduleOptions options;
  options.ramp_time_s = 0.4;
  validate_drive_schedule(kKin, plan, options);
  for (const double start : {1.0, 2.0}) {
    const std::size_t i = start < 1.5 ? 1 : 2;
    const BodyVelocityCommand& a = plan[i - 1].command;
    const BodyVelocityCommand& b = plan[i].command;
    // Continuous at both ends of the ramp.
    const WheelCommands before = wheel_commands(kKin, plan[i - 1].mode, a);
    const WheelCommands after = wheel_commands(kKin, plan[i].mode, b);
    const WheelCommands at_start = wheel_commands_at(kKin, plan, start, options);
    const WheelCommands at_end = wheel_commands_at(kKin, plan, start + options.ramp_time_s - 1e-9, options);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      EXPECT_NEAR(at_start.wheel_speed_radps[leg], before.wheel_speed_radps[leg], 1e-9);
      EXPECT_NEAR(at_start.steer_rad[leg], before.steer_rad[leg], 1e-9);
      EXPECT_NEAR(at_end.wheel_speed_radps[leg], after.wheel_speed_radps[leg], 1e-6);
      EXPECT_NEAR(at_end.steer_rad[leg], after.steer_rad[leg], 1e-6);
    }
    // Inside: the smoothstep blend of the body velocities, rolled without scrub.
    for (const double a_frac : {0.1, 0.5, 0.9}) {
      const double s = a_frac * a_frac * (3 - 2 * a_frac);
      const BodyVelocityCommand blend{a.forward_mps + s * (b.forward_mps - a.forward_mps),
                                      a.lateral_mps + s * (b.lateral_mps - a.lateral_mps),
                                      a.yaw_rate_radps + s * (b.yaw_rate_radps - a.yaw_rate_radps)};
      expect_no_scrub(kKin, wheel_commands_at(kKin, plan, start + a_frac * options.ramp_time_s, options),
                      blend, "ramp");
    }
    // Zero slope at the ramp start: the speed change over h is O(h^2).
    const double h = 1e-4;
    const WheelCommands later = wheel_commands_at(kKin, plan, start + h, options);
    for (int leg = 0; leg < kNumLegs; ++leg)
      EXPECT_LT(std::abs(later.wheel_speed_radps[leg] - at_start.wheel_speed_radps[leg]), 1e-5);
  }
}

TEST(DriveSchedule, StoppingHoldsThePreviousSteering) {
  const std::vector<DriveCommandSegment> plan{
      {0.0, DriveMode::kSymmetricAckermann, {0.4, 0.0, 0.8}},
      {1.0, DriveMode::kSymmetricAckermann, {0.0, 0.0, 0.0}},
      {2.0, DriveMode::kSymmetricAckermann, {-0.4, 0.0, -0.8}}};
  DriveScheduleOptions options;
  options.ramp_time_s = 0.5;
  const WheelCommands turning = wheel_commands(kKin, plan[0].mode, plan[0].command);
  for (const double t : {1.2, 1.5, 1.9, 2.0, 2.3, 3.0}) {
    const WheelCommands w = wheel_commands_at(kKin, plan, t, options);
    for (int leg = 0; leg < kNumLegs; ++leg)
      EXPECT_NEAR(w.steer_rad[leg], turning.steer_rad[leg], 1e-9) << t;  // same ICR throughout
  }
}

// The compiled lookup gives exactly the commands of wheel_commands_at, in the
// steady stretches and inside the ramps (same mode and mode change).
TEST(DriveSchedule, CompiledLookupMatchesTheDirectEvaluation) {
  const std::vector<DriveCommandSegment> plan{
      {0.0, DriveMode::kSymmetricAckermann, {0.5, 0.0, 0.0}},
      {1.0, DriveMode::kSymmetricAckermann, {0.5, 0.0, 1.0}},
      {2.0, DriveMode::kLateral, {0.0, 0.3, 0.0}},
      {3.0, DriveMode::kSymmetricAckermann, {0.0, 0.0, 0.0}}};
  for (const double ramp : {0.0, 0.4}) {
    DriveScheduleOptions options;
    options.ramp_time_s = ramp;
    const CompiledDriveSchedule compiled(kKin, plan, options);
    int in_ramps = 0;
    for (double t = 0.0; t < 4.0; t += 0.0137) {
      in_ramps += t > 1.0 && std::fmod(t, 1.0) < ramp ? 1 : 0;
      const WheelCommands expected = wheel_commands_at(kKin, plan, t, options);
      const WheelCommands got = compiled.at(t);
      for (int leg = 0; leg < kNumLegs; ++leg) {
        EXPECT_EQ(got.steer_rad[leg], expected.steer_rad[leg]) << "t " << t << " ramp " << ramp;
        EXPECT_EQ(got.wheel_speed_radps[leg], expected.wheel_speed_radps[leg]) << "t " << t;
      }
    }
    if (ramp > 0.0) {
      EXPECT_GT(in_ramps, 50);
    }
  }
  // Before the first segment: its commands (wheel_commands_at throws there).
  const CompiledDriveSchedule late(kKin, {{0.5, DriveMode::kParallel, {0.3, 0.0, 0.0}}});
  EXPECT_EQ(late.at(0.0).wheel_speed_radps, wheel_commands(kKin, DriveMode::kParallel, {0.3, 0.0, 0.0}).wheel_speed_radps);
}

TEST(DriveSchedule, CompilingRejectsWhatValidationRejects) {
  const BodyVelocityCommand go{0.3, 0.0, 0.0};
  DriveScheduleOptions ramp;
  ramp.ramp_time_s = 0.5;
  EXPECT_THROW(CompiledDriveSchedule(kKin, {}), std::invalid_argument);
  EXPECT_THROW(CompiledDriveSchedule(kKin, {{0.0, DriveMode::kParallel, go},
                                            {1.0, DriveMode::kParallel, go},
                                            {1.2, DriveMode::kParallel, go}},
                                     ramp),
               std::invalid_argument);  // segment 1 is shorter than the ramp
  try {
    CompiledDriveSchedule(kKin, {{0.0, DriveMode::kParallel, go}, {1.0, DriveMode::kLateral, go}});
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("segment 1"), std::string::npos) << e.what();
  }
  // A ramp whose blend the end-stop cannot serve: crabbing left at 71.6 deg
  // forward, then at 71.6 deg backward (served as -71.6 deg rolling backward);
  // half-way the blend moves straight left, at 90 deg, beyond an 80 deg limit
  // (and so is its flip, -90 deg).
  RoverParameters p = default_rover_parameters();
  p.steering.limit_rad = 80.0 * kPi / 180.0;
  const DriveKinematics narrow = make_drive_kinematics(p);
  const std::vector<DriveCommandSegment> sweep{{0.0, DriveMode::kParallel, {0.1, 0.3, 0.0}},
                                               {1.0, DriveMode::kParallel, {-0.1, 0.3, 0.0}}};
  EXPECT_NO_THROW(validate_drive_schedule(narrow, sweep, ramp));  // the steady commands pass
  EXPECT_NO_THROW(CompiledDriveSchedule(narrow, sweep));          // and without a ramp
  EXPECT_THROW(CompiledDriveSchedule(narrow, sweep, ramp), std::invalid_argument);
}

TEST(DriveSchedule, IllFormedSchedulesAreRejected) {
  const BodyVelocityCommand go{0.3, 0.0, 0.0};
  DriveScheduleOptions ramp;
  ramp.ramp_time_s = 0.5;
  EXPECT_THROW(wheel_commands_at(kKin, {}, 0.0), std::invalid_argument);
  EXPECT_THROW(wheel_commands_at(kKin, {{1.0, DriveMode::kParallel, go}, {0.5, DriveMode::kParallel, go}}, 2.0),
               std::invalid_argument);
  EXPECT_THROW(validate_drive_schedule(kKin, {{0.0, DriveMode::kParallel, go},
                                              {1.0, DriveMode::kParallel, go},
                                              {1.2, DriveMode::kParallel, go}},
                                       ramp),
               std::invalid_argument);  // segment 1 is shorter than the ramp
  try {
    validate_drive_schedule(kKin, {{0.0, DriveMode::kParallel, go},
                                   {1.0, DriveMode::kLateral, go}});
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("segment 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rover
