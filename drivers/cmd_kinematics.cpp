// `rover kinematics`: the wheel commands (steering angles d_j and rolling
// speeds dz_j/dt) of one driving-mode command (core/drive_kinematics.hpp;
// paper section 2.1, docs/model.md §1–3 and 5), as a table or JSON. A command
// the mode cannot serve, or whose wheel commands are not finite numbers, is
// an error naming the flags given.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <initializer_list>
#include <iostream>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/drive_kinematics.hpp"
#include "core/model_scale.hpp"
#include "drivers/command_registry.hpp"
#include "drivers/options.hpp"
#include "io/json_reader.hpp"
#include "io/rover_config.hpp"

namespace rover::cli {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// A crab angle beyond a half turn names a heading a smaller one names.
constexpr double kMaxCrabAngle_deg = 180.0;

struct KinematicsOptions {
  std::string config = kDefaultRoverConfig;
  CLI::Option* config_option = nullptr;
  std::string mode;
  double speed_mps = 0.0;
  double radius_m = std::numeric_limits<double>::infinity();
  double icr_x_m = 0.0, icr_y_m = 0.0;
  double crab_deg = 0.0;  // within +-kMaxCrabAngle_deg: a larger angle is the same heading
  double yaw_rate_radps = 0.0;
  double vx_mps = 0.0, vy_mps = 0.0;
  bool no_flip = false;
  bool json = false;
  // Which options were given (filled after parsing).
  CLI::Option *speed = nullptr, *radius = nullptr, *icr_x = nullptr, *icr_y = nullptr,
              *crab = nullptr, *yaw_rate = nullptr, *vx = nullptr, *vy = nullptr;
};

bool given(const CLI::Option* o) { return o != nullptr && o->count() > 0; }

// The options a mode's natural parameters use, by mode.
std::vector<std::pair<const CLI::Option*, const char*>> natural_options(const KinematicsOptions& o) {
  return {{o.speed, "--v"}, {o.radius, "--radius"}, {o.icr_x, "--icr-x"},
          {o.icr_y, "--icr-y"}, {o.crab, "--crab-deg"}};
}

void require_only(const KinematicsOptions& o, DriveMode mode,
                  const std::vector<std::string>& allowed, const std::vector<std::string>& required) {
  for (const auto& [option, name] : natural_options(o)) {
    const bool is_allowed =
        std::find(allowed.begin(), allowed.end(), std::string(name)) != allowed.end();
    if (given(option) && !is_allowed) {
      throw std::invalid_argument(std::string(name) + " is not a parameter of the " +
                                  std::string(drive_mode_keyword(mode)) + " mode");
    }
  }
  for (const auto& [option, name] : natural_options(o)) {
    const bool is_required =
        std::find(required.begin(), required.end(), std::string(name)) != required.end();
    if (is_required && !given(option)) {
      throw std::invalid_argument("the " + std::string(drive_mode_keyword(mode)) + " mode needs " +
                                  name);
    }
  }
}

DriveCommand command_from_options(const KinematicsOptions& o, const DriveKinematics& kin,
                                  DriveMode mode, const WheelCommandOptions& wheel_options) {
  const bool body = given(o.vx) || given(o.vy) ||
                    (given(o.yaw_rate) && mode != DriveMode::kInPlaceRotation);
  if (body) {
    for (const auto& [option, name] : natural_options(o)) {
      if (given(option)) {
        throw std::invalid_argument(std::string(name) +
                                    " cannot be combined with a body velocity command "
                                    "(--vx, --vy, --yaw-rate)");
      }
    }
    return drive_command(kin, mode, {o.vx_mps, o.vy_mps, o.yaw_rate_radps},
                         wheel_options.velocity_tolerance_mps);
  }
  switch (mode) {
    case DriveMode::kCarLike:
      require_only(o, mode, {"--v", "--radius"}, {"--v"});
      return car_like_command(kin, o.speed_mps, o.radius_m);
    case DriveMode::kSymmetricAckermann:
      require_only(o, mode, {"--v", "--radius"}, {"--v"});
      return symmetric_ackermann_command(kin, o.speed_mps, o.radius_m);
    case DriveMode::kGeneralAckermann:
      require_only(o, mode, {"--v", "--icr-x", "--icr-y"}, {"--v", "--icr-x", "--icr-y"});
      return general_ackermann_command(o.speed_mps, Vec2(o.icr_x_m, o.icr_y_m));
    case DriveMode::kParallel:
      require_only(o, mode, {"--v", "--crab-deg"}, {"--v"});
      if (!(std::abs(o.crab_deg) <= kMaxCrabAngle_deg))
        throw std::invalid_argument("--crab-deg must lie in [-" + number_text(kMaxCrabAngle_deg) + ", " +
                                    number_text(kMaxCrabAngle_deg) + "], got " + number_text(o.crab_deg));
      return parallel_command(o.speed_mps, o.crab_deg / kDegPerRad);
    case DriveMode::kLateral:
      require_only(o, mode, {"--v"}, {"--v"});
      return lateral_command(o.speed_mps);
    case DriveMode::kInPlaceRotation:
      require_only(o, mode, {}, {});
      if (!given(o.yaw_rate)) throw std::invalid_argument("the rotation mode needs --yaw-rate");
      return in_place_rotation_command(o.yaw_rate_radps);
  }
  throw std::invalid_argument("unknown mode");
}

// The console table of `rover kinematics`: the body velocity, the ICR, and
// each wheel's steering angle and speed.
void print_wheel_table(std::ostream& out, DriveMode mode, const std::string& config, const DriveKinematics& kin,
                       const PlanarMotion& motion, const WheelCommands& wheels) {
  const BodyVelocityCommand body = body_velocity(motion);
  const bool has_icr = motion.kind == PlanarMotion::Kind::kRotation;
  std::ostringstream s;
  s << std::fixed << std::setprecision(4);
  s << drive_mode_name(mode) << " mode (" << config << "; steering limit +-"
    << std::setprecision(1) << kin.steering_limit_rad * kDegPerRad << " deg, wheel radius "
    << std::setprecision(4) << kin.wheel_radius_m << " m)\n";
  s << "body velocity at G: v_x " << body.forward_mps << " m/s, v_y " << body.lateral_mps
    << " m/s, yaw rate " << body.yaw_rate_radps << " rad/s";
  if (has_icr) {
    s << "; ICR (" << motion.icr_m.x() << ", " << motion.icr_m.y() << ") m";
  } else if (motion.kind == PlanarMotion::Kind::kTranslation) {
    s << "; ICR at infinity";
  }
  s << "\n\n";
  s << "wheel  centre x [m]  centre y [m]  steer [rad]  steer [deg]  speed [rad/s]  ground [m/s]\n";
  for (int leg = 0; leg < kNumLegs; ++leg) {
    s << std::setw(5) << kWheelNames[leg] << std::setw(14) << kin.wheel_centre_m[leg].x()
      << std::setw(14) << kin.wheel_centre_m[leg].y() << std::setw(13) << wheels.steer_rad[leg]
      << std::setw(13) << std::setprecision(2) << wheels.steer_rad[leg] * kDegPerRad
      << std::setprecision(4) << std::setw(15) << wheels.wheel_speed_radps[leg] << std::setw(14)
      << wheels.wheel_speed_radps[leg] * kin.wheel_radius_m
      << (wheels.flipped[leg] ? "  (flipped)" : "") << "\n";
  }
  out << s.str();
}

// Speeds, rates and distances within the rover's scale (core/model_scale.hpp).
void check_scale(const KinematicsOptions& o, FlagChecks& checks) {
  auto within = [&](const CLI::Option* option, double value, double bound, const char* unit, const std::string& why) {
    if (!given(option) || !std::isfinite(value)) return;
    if (const std::string problem = beyond_scale(value, bound, unit, why); !problem.empty())
      checks.add(option->get_name() + " " + problem);
  };
  using Given = std::initializer_list<std::pair<const CLI::Option*, double>>;
  for (const auto& [option, value] : Given{{o.speed, o.speed_mps}, {o.vx, o.vx_mps}, {o.vy, o.vy_mps}})
    within(option, value, kMaxDriveSpeed_mps, "m/s", kDriveScaleReason);
  within(o.yaw_rate, o.yaw_rate_radps, kMaxYawRate_radps, "rad/s", kDriveScaleReason);
  for (const auto& [option, value] : Given{{o.radius, o.radius_m}, {o.icr_x, o.icr_x_m}, {o.icr_y, o.icr_y_m}})
    within(option, value, kMaxCoordinate_m, "m", kPositionScaleReason);
}

int run_kinematics(const KinematicsOptions& o) {
  FlagChecks checks;
  const std::vector<std::pair<const CLI::Option*, double>> numbers = {
      {o.speed, o.speed_mps}, {o.radius, o.radius_m}, {o.icr_x, o.icr_x_m},
      {o.icr_y, o.icr_y_m},   {o.crab, o.crab_deg},   {o.yaw_rate, o.yaw_rate_radps},
      {o.vx, o.vx_mps},       {o.vy, o.vy_mps}};
  for (const auto& [option, value] : numbers)
    if (given(option)) checks.finite(option->get_name(), value);
  check_scale(o, checks);
  checks.throw_if_any();
  const std::optional<DriveMode> mode = drive_mode_from_keyword(o.mode);
  if (!mode) throw std::invalid_argument("unknown mode '" + o.mode + "'");
  const std::string config = path_option(o.config_option, o.config, kDefaultRoverConfig);
  const DriveKinematics kin = make_drive_kinematics(io::load_rover_parameters(config));
  WheelCommandOptions wheel_options;
  wheel_options.allow_flip = !o.no_flip;
  std::string given_flags;  // "--v 0.5, --radius 0", for messages
  for (const auto& [option, value] : numbers)
    if (given(option)) given_flags += (given_flags.empty() ? "" : ", ") + option->get_name() + " " + number_text(value);
  DriveCommand command;
  WheelCommands wheels;
  try {
    command = command_from_options(o, kin, *mode, wheel_options);
    wheels = wheel_commands(kin, command, wheel_options);
  } catch (const std::invalid_argument& e) {
    throw CommandLineError({"the command (" + given_flags + "): " + e.what()});
  }
  const BodyVelocityCommand body = body_velocity(command.motion);
  // The yaw rate a --radius or an ICR gives at --v, within the rover's scale
  // as a scenario's drive segment is (io/scenario_config.cpp).
  if (!given(o.yaw_rate))
    if (const std::string p = beyond_scale(body.yaw_rate_radps, kMaxYawRate_radps, "rad/s", kDriveScaleReason);
        std::isfinite(body.yaw_rate_radps) && !p.empty())
      throw CommandLineError({"the command (" + given_flags + ") gives a yaw rate beyond the rover's scale: " + p});
  const bool has_icr = command.motion.kind == PlanarMotion::Kind::kRotation;

  io::Json out;
  out["mode"] = std::string(drive_mode_keyword(*mode));
  out["config"] = config;
  out["steering_limit_rad"] = kin.steering_limit_rad;
  out["wheel_radius_m"] = kin.wheel_radius_m;
  out["body_velocity"] = {{"forward_mps", body.forward_mps},
                          {"lateral_mps", body.lateral_mps},
                          {"yaw_rate_radps", body.yaw_rate_radps}};
  out["icr_m"] = has_icr ? io::Json{command.motion.icr_m.x(), command.motion.icr_m.y()}
                         : io::Json(nullptr);
  out["wheels"] = io::Json::array();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    out["wheels"].push_back(
        {{"name", kWheelNames[leg]},
         {"centre_m", {kin.wheel_centre_m[leg].x(), kin.wheel_centre_m[leg].y()}},
         {"steer_rad", wheels.steer_rad[leg]},
         {"steer_deg", wheels.steer_rad[leg] * kDegPerRad},
         {"wheel_speed_radps", wheels.wheel_speed_radps[leg]},
         {"ground_speed_mps", wheels.wheel_speed_radps[leg] * kin.wheel_radius_m},
         {"flipped", wheels.flipped[leg]}});
  }
  // A command too large for doubles (--v 1e308) is refused, table or JSON.
  try {
    require_finite_output(out);
  } catch (const std::runtime_error& e) {
    throw CommandLineError({"the command (" + given_flags + ") gives " + e.what()});
  }
  if (o.json) {
    std::cout << out.dump(2) << "\n";
    return 0;
  }

  print_wheel_table(std::cout, *mode, config, kin, command.motion, wheels);
  return 0;
}

const RegisterCommand kinematics_command{
    60, "kinematics",
    "Wheel commands (4 steering angles, 4 wheel speeds) of a driving-mode command",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<KinematicsOptions>();
      app.footer(
          "Decomposes a motion command into the steering angles d_j (+ = wheel heading turned "
          "left) and the wheel rolling speeds dz_j/dt (+ = rolling forward; ground speed / R_w) of "
          "the wheels FL FR RL RR, with chassis axes x forward, y left, origin G (docs/model.md §1-3).\n"
          "Give a mode and either its natural parameters or a body velocity at G:\n"
          "  car                --v --radius      rear wheels straight; speed and turning radius\n"
          "                                       of the rear-axle centre (+radius = turn left)\n"
          "  ackermann          --v --radius      front and rear steer opposite; radius from the\n"
          "                                       point midway between the axles (G)\n"
          "  general-ackermann  --v --icr-x --icr-y  any ICR; --v is the speed of G\n"
          "  parallel           --v --crab-deg    all wheels parallel (crab)\n"
          "  lateral            --v               sideways, + = left\n"
          "  rotation           --yaw-rate        in place about G\n"
          "  body command       --vx --vy --yaw-rate (any mode; rejected if the mode cannot\n"
          "                                       represent it)\n"
          "Without --radius the Ackermann modes drive straight. A wheel whose heading would pass "
          "the steering end-stop is turned by 180 deg and rolled backward (marked 'flipped'); "
          "with --no-flip such a command is rejected instead. Nothing is ever clamped.\n\n"
          "Examples:\n"
          "  rover kinematics --mode ackermann --v 0.5 --radius 1.0\n"
          "  rover kinematics --mode rotation --yaw-rate 0.5 --json\n"
          "  rover kinematics --mode general-ackermann --vx 0.3 --vy 0.1 --yaw-rate 0.2");
      o->config_option = app.add_option("--config", o->config, "Rover parameters (JSON)")
                             ->capture_default_str()
                             ->check(CLI::ExistingFile);
      std::vector<std::string> keywords;
      for (const DriveMode m : kAllDriveModes) keywords.emplace_back(drive_mode_keyword(m));
      app.add_option("--mode", o->mode, "Driving mode")->required()->check(CLI::IsMember(keywords));
      o->speed = app.add_option("--v", o->speed_mps, "Speed [m/s] (negative = reversing)");
      o->radius = app.add_option("--radius", o->radius_m,
                                 "Turning radius [m], + = ICR on the left (car, ackermann); omit to drive straight");
      o->icr_x = app.add_option("--icr-x", o->icr_x_m, "ICR x in the chassis frame [m]");
      o->icr_y = app.add_option("--icr-y", o->icr_y_m, "ICR y in the chassis frame [m]");
      o->crab = app.add_option("--crab-deg", o->crab_deg, "Crab angle [deg], + = left (parallel)");
      o->yaw_rate = app.add_option("--yaw-rate", o->yaw_rate_radps, "Yaw rate [rad/s], + = left");
      o->vx = app.add_option("--vx", o->vx_mps, "Body command: forward velocity of G [m/s]");
      o->vy = app.add_option("--vy", o->vy_mps, "Body command: lateral velocity of G [m/s]");
      app.add_flag("--no-flip", o->no_flip,
                   "Reject headings beyond the end-stop instead of flipping the wheel");
      app.add_flag("--json", o->json, "Print JSON instead of a table");
      return [o] { return run_kinematics(*o); };
    }};

}  // namespace
}  // namespace rover::cli
