// See scenario_config.hpp.
#include "io/scenario_config.hpp"
#include "io/config_kind.hpp"
#include "io/output_target.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/contact.hpp"
#include "core/kinematic_tree.hpp"
#include "core/model_scale.hpp"
#include "core/number_text.hpp"
#include "io/csv.hpp"
#include "io/model_config.hpp"
#include "io/process_memory.hpp"
#include "io/rover_config.hpp"
#include "io/terrain_json.hpp"

namespace rover::io {
namespace {

int coordinate_index(const JsonReader& r, const std::string& name) {
  for (int i = 0; i < kNumCoordinates; ++i)
    if (name == kCoordinateNames[i]) return i;
  r.fail(name, "unknown coordinate name (use x y z theta chi psi phi b11 b12 b21 b22 b31 b32 b41 "
               "b42 d1 d2 d3 d4 z1 z2 z3 z4)");
}

// The named entries of parent[key] over `c` (entries not named keep their value).
Coordinates parse_named_coordinates(const JsonReader& parent, const std::string& key,
                                    Coordinates c = Coordinates::Zero()) {
  if (!parent.has(key)) return c;
  const JsonReader r = parent.child(key);
  for (const auto& [name, value] : r.raw_object().items()) c[coordinate_index(r, name)] = r.number(name);
  r.finish();
  return c;
}

// The initial position of G within the scale a double resolves (core/model_scale.hpp).
void check_initial_position(const JsonReader& r, const Coordinates& q) {
  constexpr std::array<std::pair<const char*, int>, 3> kPosition = {
      {{"x", coord::x}, {"y", coord::y}, {"z", coord::z}}};
  for (const auto& [name, index] : kPosition) {
    const std::string problem = beyond_scale(q[index], kMaxCoordinate_m, "m", kPositionScaleReason);
    if (problem.empty()) continue;
    if (index == coord::z && r.has("initial_ground_clearance"))
      r.fail("initial_ground_clearance", "puts G at z = " + problem);
    r.fail("initial_q", std::string(name) + " = " + problem);
  }
}

// The speeds of initial_u (also those a drive or forward_speed set) and the
// rates of wheel_speed_ref within the rover's scale.
void check_initial_speeds(const JsonReader& r, const Scenario& s, const SpeedScale& scale) {
  const double wheel_radius_m = scale.wheel_radius_m;
  for (int index = 0; index < kNumCoordinates; ++index)
    if (const std::string p = speed_beyond_scale(index, s.initial_u[index], scale); !p.empty())
      r.fail(r.has("initial_u") ? "initial_u" : "drive", std::string(kCoordinateNames[index]) + " = " + p);
  if (!r.has("wheel_speed_ref")) return;
  for (int leg = 0; leg < kNumLegs; ++leg)
    if (const std::string p = rate_beyond_scale(s.wheel_speed_ref_radps[leg], wheel_radius_m); !p.empty())
      r.fail("wheel_speed_ref", "element " + std::to_string(leg) + ": " + p);
}

// A drive's ramp_time longer than the run: no segment after the first would
// reach its command within it (a time in milliseconds typed as seconds).
void refuse_ramp_beyond_the_end(const JsonReader& drive, const Scenario& s) {
  const double ramp = s.drive.options.ramp_time_s;
  if (s.drive.segments.size() < 2 || ramp <= s.duration_s) return;
  drive.fail("ramp_time", number_text(ramp) + " s is longer than the run (duration " + number_text(s.duration_s) +
                              " s): no segment after the first would reach its command within the run; give the "
                              "ramp in seconds, at most the duration");
}

// Lowest wheel-bottom height below the chassis origin at the given pose.
double lowest_wheel_bottom(const RoverModel& model, const Coordinates& q) {
  Coordinates level = q;
  level[coord::z] = 0.0;
  const TreeKinematics kin = forward_kinematics(model.tree, level, Coordinates::Zero());
  double lowest = std::numeric_limits<double>::infinity();
  const double R = model.parameters.geometry.wheel_radius_m;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const NodeKinematics& w = kin.nodes[node::wheel(leg)];
    const Vec3 s = w.rotation.col(1);
    lowest = std::min(lowest, w.origin.z() - R * std::sqrt(std::max(0.0, 1.0 - s.z() * s.z())));
  }
  return lowest;
}

// The fastest the rover's chassis can move over the run: its initial
// horizontal speed, its wheel speed references at the rim and every drive
// segment's body velocity.
double fastest_horizontal_speed(const Scenario& s, double wheel_radius_m) {
  double v = std::hypot(s.initial_u[coord::x], s.initial_u[coord::y]);
  for (int leg = 0; leg < kNumLegs; ++leg) v = std::max(v, std::abs(s.wheel_speed_ref_radps[leg]) * wheel_radius_m);
  for (const DriveCommandSegment& segment : s.drive.segments)
    v = std::max(v, std::hypot(segment.command.forward_mps, segment.command.lateral_mps));
  return v;
}

// How far the wheels reach horizontally from G at pose `q`: the farthest
// wheel centre plus the wheel radius.
double wheel_reach_m(const RoverModel& model, const Coordinates& q) {
  const TreeKinematics kin = forward_kinematics(model.tree, q, Coordinates::Zero());
  double reach = 0.0;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec3& w = kin.nodes[node::wheel(leg)].origin;
    reach = std::max(reach, std::hypot(w.x() - q[coord::x], w.y() - q[coord::y]));
  }
  return reach + model.parameters.geometry.wheel_radius_m;
}

// A terrain grid the rover cannot reach within the run (it starts farther
// from the grid than its speeds carry it in the duration): the run would be
// on the grid's flat extension, its obstacle never met; a position in
// millimetres typed as metres.
void refuse_runs_beside_the_grid(const JsonReader& r, const ScenarioSetup& setup) {
  const HeightGrid* grid = setup.model.terrain.grid();
  if (grid == nullptr) return;
  const Scenario& s = setup.scenario;
  const double x = s.initial_q[coord::x], y = s.initial_q[coord::y];
  const double x_end = grid->node_x(grid->nx - 1), y_end = grid->node_y(grid->ny - 1);
  const double dx = std::max({0.0, grid->origin_x_m - x, x - x_end});
  const double dy = std::max({0.0, grid->origin_y_m - y, y - y_end});
  const double gap = std::hypot(dx, dy) - wheel_reach_m(setup.model, s.initial_q);
  const double speed = fastest_horizontal_speed(s, setup.model.parameters.geometry.wheel_radius_m);
  const double travel = speed * s.duration_s;
  if (!(gap > travel)) return;
  const char* field = r.has("initial_q") ? "initial_q" : "terrain";
  r.fail(field, "the rover starts at x = " + number_text(x) + " m, y = " + number_text(y) + " m, " + number_text(gap) +
                    " m from the terrain grid of " + setup.terrain_path + " (x " + number_text(grid->origin_x_m) +
                    " .. " + number_text(x_end) + " m, y " + number_text(grid->origin_y_m) + " .. " +
                    number_text(y_end) + " m), and moves at most " + number_text(travel) + " m in the run (" +
                    number_text(speed) + " m/s for " + number_text(s.duration_s) +
                    " s): it never reaches the grid; a position in millimetres, or too short a run?");
}

// ---- "drive": a time-varying driving command ----------------------

constexpr const char* kModeKeywords =
    "car, ackermann, general-ackermann, parallel, lateral, rotation";

// A command given by its mode's natural parameters ("speed" and the geometry).
DriveCommand natural_command(const JsonReader& s, const DriveKinematics& k, DriveMode mode) {
  constexpr double kStraight = std::numeric_limits<double>::infinity();
  const double speed = s.number("speed");
  switch (mode) {
    case DriveMode::kCarLike:
      return car_like_command(k, speed, s.number_or("radius", kStraight));
    case DriveMode::kSymmetricAckermann:
      return symmetric_ackermann_command(k, speed, s.number_or("radius", kStraight));
    case DriveMode::kGeneralAckermann: {
      const auto icr = s.fixed_numbers<2>("icr");
      return general_ackermann_command(speed, Vec2(icr[0], icr[1]));
    }
    case DriveMode::kParallel: {
      const double crab_rad = s.number_or("crab_angle", 0.0);
      // An angle beyond a half turn is a heading in degrees, not radians.
      if (!(std::abs(crab_rad) <= std::numbers::pi))
        s.fail("crab_angle", "must lie in [-pi, pi] rad (an angle in degrees?)");
      return parallel_command(speed, crab_rad);
    }
    case DriveMode::kLateral:
      return lateral_command(speed);
    case DriveMode::kInPlaceRotation:
      break;
  }
  s.fail("speed", "the rotation mode is commanded by 'yaw_rate' [rad/s] alone");
}

// A segment's speeds, rates and geometry within the scales of core/model_scale.hpp.
// Reads the values without marking their keys as used: a key the mode does not
// take is still reported by finish().
void check_drive_scale(const JsonReader& s, bool natural) {
  const Json& object = s.raw_object();
  auto check = [&](const char* key, const Json& value, double bound, const char* unit, const std::string& why) {
    if (!value.is_number()) return;  // the parsers report a wrong type
    if (const std::string p = beyond_scale(value.get<double>(), bound, unit, why); !p.empty()) s.fail(key, p);
  };
  auto within = [&](const char* key, double bound, const char* unit, const std::string& why) {
    if (object.contains(key)) check(key, object.at(key), bound, unit, why);
  };
  if (natural) {
    within("speed", kMaxDriveSpeed_mps, "m/s", kDriveScaleReason);
    within("radius", kMaxCoordinate_m, "m", kPositionScaleReason + " (leave 'radius' out to drive straight)");
    if (object.contains("icr") && object.at("icr").is_array())
      for (const Json& c : object.at("icr")) check("icr", c, kMaxCoordinate_m, "m", kPositionScaleReason);
  } else {
    within("forward", kMaxDriveSpeed_mps, "m/s", kDriveScaleReason);
    within("lateral", kMaxDriveSpeed_mps, "m/s", kDriveScaleReason);
    within("yaw_rate", kMaxYawRate_radps, "rad/s", kDriveScaleReason);
  }
}

// One element of "segments"; `where` is its field path ("drive.segments[1]").
DriveCommandSegment parse_drive_segment(const Json& json, const std::string& file,
                                        const std::string& where, const DriveKinematics& k,
                                        const WheelCommandOptions& wheel_options, bool first) {
  const JsonReader s(json, file, where);
  DriveCommandSegment segment;
  segment.start_time_s = first ? s.number_or("start", 0.0) : s.number("start");
  if (first && segment.start_time_s != 0.0)
    s.fail("start", "the first segment must start at 0 s, where the simulation starts");
  const std::string keyword = s.string("mode");
  const std::optional<DriveMode> mode = drive_mode_from_keyword(keyword);
  if (!mode) s.fail("mode", std::string("unknown driving mode (known: ") + kModeKeywords + ")");
  segment.mode = *mode;

  const bool natural = s.has("speed");
  for (const char* key : {"forward", "lateral", "yaw_rate"}) {
    if (natural && s.has(key))
      s.fail(key, "give either 'speed' with the mode's geometry (radius, icr, crab_angle) or the "
                  "body velocity 'forward', 'lateral', 'yaw_rate', not both");
  }
  for (const char* key : {"radius", "icr", "crab_angle"}) {
    if (!natural && s.has(key)) s.fail(key, "needs 'speed' [m/s] in the same segment");
  }
  check_drive_scale(s, natural);
  try {
    if (natural) {
      segment.command = body_velocity(natural_command(s, k, segment.mode).motion);
    } else {
      segment.command = {s.number_or("forward", 0.0), s.number_or("lateral", 0.0),
                         s.number_or("yaw_rate", 0.0)};
    }
    // Can the mode serve it within the end-stops? (The whole schedule is
    // checked again below, with the steering each wheel holds when at rest.)
    wheel_commands(k, segment.mode, segment.command, wheel_options);
  } catch (const std::invalid_argument& e) {
    throw ConfigError(file + ": field '" + where + "': " + e.what());
  }
  if (const std::string p = beyond_scale(segment.command.yaw_rate_radps, kMaxYawRate_radps, "rad/s", kDriveScaleReason);
      natural && !p.empty())
    s.fail(s.raw_object().contains("radius") ? "radius" : "icr", "gives a yaw rate beyond the rover's scale: " + p);
  s.finish();
  return segment;
}

// A drive segment that starts at or after the run's end would never act.
void refuse_segments_after_the_end(const JsonReader& drive, const Scenario& s) {
  for (std::size_t i = 0; i < s.drive.segments.size(); ++i) {
    const double start = s.drive.segments[i].start_time_s;
    if (start < s.duration_s) continue;
    const JsonReader segment(drive.raw("segments")[i], drive.file(),
                             drive.field("segments") + "[" + std::to_string(i) + "]");
    segment.fail("start", number_text(start) + " s is not before the run's end (duration " +
                              number_text(s.duration_s) + " s): the segment would never act; remove it or "
                              "lengthen the duration");
  }
}

// The speeds that match a drive command: the chassis moves with the body
// velocity (turned by the yaw into the world frame), every wheel spins at its
// commanded rate.
Coordinates commanded_speeds(const BodyVelocityCommand& v, const WheelCommands& w,
                             double yaw_rad) {
  Coordinates u = Coordinates::Zero();
  const double c = std::cos(yaw_rad), sn = std::sin(yaw_rad);
  u[coord::x] = c * v.forward_mps - sn * v.lateral_mps;
  u[coord::y] = sn * v.forward_mps + c * v.lateral_mps;
  u[coord::yaw] = v.yaw_rate_radps;
  for (int leg = 0; leg < kNumLegs; ++leg) u[coord::spin(leg)] = w.wheel_speed_radps[leg];
  return u;
}

}  // namespace

double max_rate_radps(double wheel_radius_m) { return kMaxDriveSpeed_mps / wheel_radius_m; }

std::string rate_beyond_scale(double rate_radps, double wheel_radius_m) {
  return beyond_scale(rate_radps, max_rate_radps(wheel_radius_m), "rad/s",
                      "the rate that moves a wheel rim at " + number_text(kMaxDriveSpeed_mps) +
                          " m/s (wheel radius " + number_text(wheel_radius_m) + " m), " + kDriveScaleReason);
}

SpeedScale speed_scale(const RoverModel& model) {
  const TreeKinematics kin = forward_kinematics(model.tree, Coordinates::Zero(), Coordinates::Zero());
  double farthest = 0.0;
  for (int leg = 0; leg < kNumLegs; ++leg) farthest = std::max(farthest, kin.nodes[node::wheel(leg)].origin.norm());
  const double radius = model.parameters.geometry.wheel_radius_m;
  return {radius, farthest + radius};
}

std::string speed_beyond_scale(int index, double value, const SpeedScale& scale) {
  if (index == coord::x || index == coord::y || index == coord::z)
    return beyond_scale(value, kMaxDriveSpeed_mps, "m/s", kDriveScaleReason);
  if (index == coord::yaw || index == coord::pitch || index == coord::roll)
    return beyond_scale(value, kMaxDriveSpeed_mps / scale.rover_extent_m, "rad/s",
                        "the rate that turns the rover's farthest point (a wheel rim " +
                            number_text(scale.rover_extent_m) + " m from G) at " + number_text(kMaxDriveSpeed_mps) +
                            " m/s, " + kDriveScaleReason);
  return rate_beyond_scale(value, scale.wheel_radius_m);
}

DriveConfig parse_drive(const JsonReader& r, const DriveKinematics& kinematics) {
  DriveConfig config;
  DriveSchedule& drive = config.schedule;
  if (r.has("ramp_time")) drive.options.ramp_time_s = r.non_negative("ramp_time");
  drive.options.wheel.allow_flip = r.boolean_or("allow_flip", true);
  const std::string initial = r.string_or("initial_motion", "commanded");
  if (initial != "commanded" && initial != "rest")
    r.fail("initial_motion", "expected \"commanded\" or \"rest\"");
  config.start_at_rest = initial == "rest";

  const Json& list = r.raw("segments");
  if (!list.is_array() || list.empty())
    r.fail("segments", "expected a non-empty array of segments {\"start\", \"mode\", ...}");
  for (std::size_t i = 0; i < list.size(); ++i) {
    drive.segments.push_back(parse_drive_segment(list[i], r.file(),
                                                 r.field("segments") + "[" + std::to_string(i) + "]",
                                                 kinematics, drive.options.wheel, i == 0));
  }
  try {
    config.commands_at_start = CompiledDriveSchedule(kinematics, drive.segments, drive.options).at(0.0);
  } catch (const std::invalid_argument& e) {
    r.fail("segments", e.what());
  }
  r.finish();
  return config;
}

double recorded_sample_count(double duration_s, double rate_hz) {
  return std::floor(duration_s * rate_hz * (1.0 + 1e-12)) + 1.0;
}

std::string recording_size_problem(double samples, double bytes_per_sample, double max_bytes,
                                   const std::string& limit_name) {
  const double bytes = samples * bytes_per_sample;
  if (bytes <= max_bytes) return "";
  constexpr std::array<const char*, 7> kUnits{"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  double amount = bytes;
  std::size_t unit = 0;
  while (amount >= 1000.0 && unit + 1 < kUnits.size()) {
    amount /= 1000.0;
    ++unit;
  }
  char text[120];
  std::snprintf(text, sizeof text, "would record %.1e samples (%.3g %s, more than the %.3g GB ", samples, amount,
                kUnits[unit], max_bytes / 1e9);
  return text + (limit_name.empty() ? std::string("allowed") : "of " + limit_name) + ")";
}

double initial_penetration_tolerance_m(const RoverModel& model) {
  const RoverParameters& p = model.parameters;
  const double weight_N = model.tree.total_mass_kg * p.gravity_mps2;
  const double one_wheel_m =
      std::pow(weight_N / p.contact.stiffness_k_g, 1.0 / p.contact.exponent_sigma);
  return std::max(1e-3, one_wheel_m);
}

WheelPenetration deepest_wheel_penetration(const RoverModel& model, const Coordinates& q) {
  const TreeKinematics kin = forward_kinematics(model.tree, q, Coordinates::Zero());
  WheelPenetration deepest;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const NodeKinematics& wheel = kin.nodes[node::wheel(leg)];
    const WheelContacts contacts = find_wheel_contacts(model.terrain, wheel.origin, wheel.rotation.col(1),
                                                       model.parameters.geometry.wheel_radius_m);
    for (int k = 0; k < contacts.count; ++k) {
      if (contacts.points[k].depth_m > deepest.depth_m) {
        deepest.depth_m = contacts.points[k].depth_m;
        deepest.leg = leg;
      }
    }
  }
  return deepest;
}

namespace {

// What is wrong with the chassis's orientation, the bogie's angle and the
// wheels' rolling angles of pose q (core/model_scale.hpp gives the bounds).
std::string body_angle_problem(const Coordinates& q) {
  struct AngleBound {
    int index;
    double bound_rad;
    const std::string* reason;
  };
  std::vector<AngleBound> bounds{{coord::yaw, kMaxTurnAngle_rad, &kHeadingScaleReason},
                                 {coord::pitch, kMaxChassisTilt_rad, &kChassisTiltScaleReason},
                                 {coord::roll, kMaxChassisTilt_rad, &kChassisTiltScaleReason},
                                 {coord::bogie, kMaxBogieAngle_rad, &kBogieAngleScaleReason}};
  for (int leg = 0; leg < kNumLegs; ++leg)
    bounds.push_back({coord::spin(leg), kMaxTurnAngle_rad, &kWheelAngleScaleReason});
  for (const AngleBound& b : bounds)
    if (const std::string p = beyond_scale(q[b.index], b.bound_rad, "rad", *b.reason); !p.empty())
      return std::string(kCoordinateNames[b.index]) + " = " + p;
  return "";
}

}  // namespace

std::string pose_angle_problem(const RoverModel& model, const Coordinates& q) {
  if (std::string problem = body_angle_problem(q); !problem.empty()) return problem;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    for (const int joint : {coord::s_joint(leg, 0), coord::s_joint(leg, 1)})
      if (const std::string p = beyond_scale(q[joint], kMaxSStructureDeflection_rad, "rad", kDeflectionScaleReason);
          !p.empty())
        return std::string(kCoordinateNames[joint]) + " = " + p;
    const int steer = coord::steer(leg);
    if (const double limit = model.parameters.steering.limit_rad; !(std::abs(q[steer]) <= limit))
      return std::string(kCoordinateNames[steer]) + " = " + number_text(q[steer]) +
             " rad is beyond the steering end-stop +-" + number_text(limit) + " rad";
  }
  return "";
}

std::string resolve_relative(const std::string& config_path, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return path;
  const std::filesystem::path joined = std::filesystem::path(config_path).parent_path() / p;
  const std::filesystem::path tidy = joined.lexically_normal();
  if (tidy == joined) return tidy.string();
  // ".." after a linked folder leaves the link's target, not the folder the
  // link stands in: the tidy name is used only where the system agrees.
  std::error_code joined_error, tidy_error;
  const std::filesystem::path joined_real = std::filesystem::weakly_canonical(joined, joined_error);
  const std::filesystem::path tidy_real = std::filesystem::weakly_canonical(tidy, tidy_error);
  return !joined_error && !tidy_error && joined_real == tidy_real ? tidy.string() : joined.string();
}

namespace {

// The step the file gives that breaks min_step <= initial_step <= max_step:
// a max_step of 1e-15 s below the default min_step is max_step's mistake.
const char* misordered_step_key(const JsonReader& r, const IntegratorSettings& s) {
  if (r.has("max_step") && !(s.max_step_s >= s.min_step_s && s.max_step_s >= s.initial_step_s)) return "max_step";
  if (r.has("min_step") && !(s.min_step_s <= s.initial_step_s && s.min_step_s <= s.max_step_s)) return "min_step";
  return "initial_step";
}

bool slip_tolerance_out(const IntegratorSettings& s) {
  const bool stiff = s.method == IntegratorMethod::kRosenbrockW || s.method == IntegratorMethod::kRodas4;
  return stiff && !(s.slip_tolerance <= IntegratorSettings::kMaxSlipTolerance);
}

}  // namespace

// A key the chosen method does not use is refused: a slip_tol on dopri5 or an
// rtol on rk4 would look like a setting while changing nothing.
void refuse_keys_the_method_ignores(const JsonReader& r, IntegratorMethod method) {
  static constexpr std::array<const char*, 5> kAdaptiveKeys = {"rtol", "atol", "initial_step", "min_step", "max_step"};
  const bool stiff = method == IntegratorMethod::kRosenbrockW || method == IntegratorMethod::kRodas4;
  const std::string name = integrator_name(method);
  if (method == IntegratorMethod::kRungeKutta4) {
    for (const char* key : kAdaptiveKeys)
      if (r.has(key)) r.fail(key, "rk4 takes fixed steps and uses only fixed_step; remove '" + std::string(key) +
                                      "' or choose an adaptive method (dopri5, rosenbrock, rodas4)");
    if (r.has("slip_tol")) r.fail("slip_tol", "only rosenbrock and rodas4 use slip_tol; remove it for rk4");
    return;
  }
  if (r.has("fixed_step"))
    r.fail("fixed_step", name + " chooses its own steps; fixed_step is used only by rk4: remove it, or bound the "
                                "steps with min_step and max_step");
  if (!stiff && r.has("slip_tol"))
    r.fail("slip_tol", "only rosenbrock and rodas4 use slip_tol; " + name + " holds the slip speed to rtol and atol "
                                                                       "like every state: remove it");
}

IntegratorSettings parse_integrator_settings(const JsonReader& r, IntegratorSettings s) {
  if (r.has("method")) {
    IntegratorMethod method = s.method;
    try {
      method = integrator_from_name(r.string("method"));
    } catch (const std::invalid_argument& e) {
      r.fail("method", e.what());
    }
    // Another method comes with all its own settings (a Rosenbrock run at
    // dopri5's rtol 1e-6, atol 1e-9 would be slow for nothing, and at its
    // min_step or max_step would fail or crawl); the fields below still
    // override them.
    if (method != s.method) s = default_integrator_settings(method);
  }
  if (r.has("rtol")) s.relative_tolerance = r.positive("rtol");
  if (r.has("atol")) s.absolute_tolerance = r.positive("atol");
  if (r.has("initial_step")) s.initial_step_s = r.positive("initial_step");
  if (r.has("min_step")) s.min_step_s = r.positive("min_step");
  if (r.has("max_step")) s.max_step_s = r.positive("max_step");
  if (r.has("fixed_step")) s.fixed_step_s = r.positive("fixed_step");
  if (r.has("slip_tol")) s.slip_tolerance = r.positive("slip_tol");
  r.finish();
  refuse_keys_the_method_ignores(r, s.method);
  if (std::string why; !s.IsValid(&why)) {
    const bool rtol_out = !(s.relative_tolerance >= IntegratorSettings::kMinRelativeTolerance &&
                            s.relative_tolerance <= IntegratorSettings::kMaxRelativeTolerance);
    const char* key = s.method == IntegratorMethod::kRungeKutta4                     ? "fixed_step"
                      : rtol_out                                                     ? "rtol"
                      : !(s.absolute_tolerance >= IntegratorSettings::kMinAbsoluteTolerance &&
                          s.absolute_tolerance <= IntegratorSettings::kMaxAbsoluteTolerance) ? "atol"
                      : slip_tolerance_out(s)                                        ? "slip_tol"
                                                                                     : misordered_step_key(r, s);
    r.fail(key, why);
  }
  // A fixed step below the adaptive methods' floor is a typo (1e-300), and its
  // step count per output period would not fit an integer.
  if (s.method == IntegratorMethod::kRungeKutta4 && !(s.fixed_step_s >= s.min_step_s))
    r.fail("fixed_step", "rk4: fixed_step " + number_text(s.fixed_step_s) + " s is below min_step " +
                             number_text(s.min_step_s) + " s");
  return s;
}

ModelInputs parse_simulation_inputs(const JsonReader& r, ModelInputs in) {
  if (r.has("f")) in.sharpness_f = read_sharpness_f(r, "f");
  if (r.has("c_q")) in.damping_c_q = read_damping_c_q(r, "c_q");
  if (r.has("M0")) in.preload_Nm = read_preloads(r, "M0");
  r.finish();
  return in;
}

namespace {

// A file read through /dev/stdin or /dev/fd/N (or /proc/self/fd/N) has no
// folder of its own: relative names in it are resolved against /dev or
// /proc. " (relative names ... )" when `config_path` is such a stream and
// `name` relative; empty otherwise.
std::string stream_folder_note(const std::string& config_path, const std::string& name) {
  if (std::filesystem::path(name).is_absolute()) return "";
  const std::string folder = std::filesystem::path(config_path).parent_path().string();
  if (folder != "/dev" && folder != "/dev/fd" && !folder.starts_with("/proc/")) return "";
  return " (" + config_path + " is a stream, not a file in a folder of yours: relative names in it are resolved "
         "against " + folder + "; give absolute paths, or save the file and give its path)";
}

}  // namespace

std::string named_input_file(const JsonReader& r, const std::string& key, const std::string& kind) {
  const std::string name = r.string(key);
  if (name.empty()) r.fail(key, "expected the path of " + kind);
  const std::string resolved = resolve_relative(r.file(), name);
  if (const std::string problem = input_path_problem(resolved, kind); problem == "no such file")
    r.fail(key, "file not found: " + resolved + stream_folder_note(r.file(), name));
  else if (!problem.empty())
    r.fail(key, resolved + " " + problem);
  return resolved;
}

ScenarioSources read_scenario_sources(const std::string& path) {
  ScenarioSources sources;
  sources.scenario = read_config_file(path, ConfigKind::kScenario);
  sources.scenario_path = path;
  const JsonReader r(sources.scenario, path);
  sources.rover_path = named_input_file(r, "rover", "a JSON file");
  if (r.has("terrain")) {
    sources.terrain_path = named_input_file(r, "terrain", "a JSON file");
    sources.terrain = load_terrain(sources.terrain_path);
  }
  sources.rover = read_config_file(sources.rover_path, ConfigKind::kRover);
  sources.files = scenario_files(sources);
  return sources;
}

InputFiles scenario_files(const ScenarioSources& sources) {
  InputFiles files;
  files.add(sources.rover_path, "'rover' in " + sources.scenario_path);
  files.add(sources.terrain_path, "'terrain' in " + sources.scenario_path);
  return files;
}

ScenarioSetup load_scenario(const std::string& path) {
  return build_scenario(read_scenario_sources(path));
}

namespace {

// The initial state and set-points: initial_q, initial_u, a drive's start,
// forward_speed, initial_ground_clearance, wheel_speed_ref and steer_ref.
void parse_initial_state(const JsonReader& r, const ScenarioSources& sources, ScenarioSetup& setup) {
  Scenario& s = setup.scenario;
  const double R = setup.model.parameters.geometry.wheel_radius_m;
  // A drive schedule replaces the constant set-points; its command at t = 0
  // gives the initial steering and, unless it starts at rest, the speeds.
  if (r.has("drive")) {
    for (const char* key : {"forward_speed", "wheel_speed_ref", "steer_ref"}) {
      if (r.has(key))
        r.fail(key, "conflicts with 'drive', whose schedule sets the wheel speed and steering "
                    "references (drive straight with a parallel or ackermann segment)");
    }
    DriveConfig drive = parse_drive(r.child("drive"), make_drive_kinematics(setup.model.parameters));
    s.drive = std::move(drive.schedule);
    const WheelCommands w0 = drive.commands_at_start;
    s.steer_ref_rad = w0.steer_rad;
    s.wheel_speed_ref_radps = w0.wheel_speed_radps;
    for (int leg = 0; leg < kNumLegs; ++leg) s.initial_q[coord::steer(leg)] = w0.steer_rad[leg];
    s.initial_q = parse_named_coordinates(r, "initial_q", s.initial_q);
    if (!drive.start_at_rest)
      s.initial_u = commanded_speeds(s.drive.segments.front().command, w0, s.initial_q[coord::yaw]);
  } else {
    s.initial_q = parse_named_coordinates(r, "initial_q");
  }
  if (const std::string problem = pose_angle_problem(setup.model, s.initial_q); !problem.empty())
    r.fail("initial_q", problem);
  s.initial_u = parse_named_coordinates(r, "initial_u", s.initial_u);
  if (r.has("forward_speed")) {
    const double v = r.number("forward_speed");
    if (const std::string beyond = beyond_scale(v, kMaxDriveSpeed_mps, "m/s", kDriveScaleReason); !beyond.empty())
      r.fail("forward_speed", beyond);
    s.initial_u[coord::x] = v;
    for (int leg = 0; leg < kNumLegs; ++leg) {
      s.initial_u[coord::spin(leg)] = v / R;
      s.wheel_speed_ref_radps[leg] = v / R;
    }
  }
  if (r.has("initial_ground_clearance")) {
    // It sets z: a z given beside it would be silently replaced.
    if (r.has("initial_q") && r.child("initial_q").has("z"))
      r.fail("initial_ground_clearance", "sets initial_q.z from the lowest wheel, but initial_q.z is given too "
                                         "(value " + number_text(s.initial_q[coord::z]) + "): give one of them");
    s.initial_q[coord::z] = r.number("initial_ground_clearance") - lowest_wheel_bottom(setup.model, s.initial_q);
  }
  check_initial_position(r, s.initial_q);
  if (r.has("wheel_speed_ref")) s.wheel_speed_ref_radps = r.fixed_numbers<kNumLegs>("wheel_speed_ref");
  check_initial_speeds(r, s, speed_scale(setup.model));
  if (r.has("steer_ref")) {
    s.steer_ref_rad = r.fixed_numbers<kNumLegs>("steer_ref");
    // Beyond the end-stop the servo would push into it for the whole run: an
    // unreachable reference is refused, never clamped (as for a drive).
    const double limit = setup.model.parameters.steering.limit_rad;
    for (int leg = 0; leg < kNumLegs; ++leg)
      if (!(std::abs(s.steer_ref_rad[leg]) <= limit))
        r.fail("steer_ref", "element " + std::to_string(leg) + " (" + number_text(s.steer_ref_rad[leg]) +
                                " rad) is beyond the steering end-stop +-" + number_text(limit) +
                                " rad (steering.limit of " + sources.rover_path + ")");
  }
}

// The run's length (duration, or travel_distance at forward_speed) and its
// output rate, within what a recorded curve needs and a file holds.
void parse_run_length(const JsonReader& r, Scenario& s) {
  if (r.has("duration") == r.has("travel_distance"))
    r.fail("duration", "give exactly one of 'duration' [s] and 'travel_distance' [m]");
  if (r.has("duration")) {
    s.duration_s = r.positive("duration");
  } else {
    if (r.has("drive")) r.fail("travel_distance", "give 'duration' [s] with 'drive'");
    const double distance = r.positive("travel_distance");
    if (!r.has("forward_speed") || !(r.number("forward_speed") > 0.0))
      r.fail("travel_distance", "needs a positive 'forward_speed'");
    s.duration_s = distance / r.number("forward_speed");
  }
  s.output_rate_hz = r.has("output_rate") ? r.positive("output_rate") : 1000.0;
  // A recorded curve needs the samples rover compare and calibrate read.
  if (const double samples = recorded_sample_count(s.duration_s, s.output_rate_hz);
      !(samples >= static_cast<double>(kMeasuredCurveMinRows)))
    r.fail(r.has("duration") ? "duration" : "travel_distance",
           "a run of " + number_text(s.duration_s) + " s at output_rate " + number_text(s.output_rate_hz) +
               " Hz records " + number_text(samples) + " sample(s), fewer than the " +
               std::to_string(kMeasuredCurveMinRows) + " of a curve rover compare and calibrate accept; the run " +
               "must last at least " + std::to_string(kMeasuredCurveMinRows - 1) + " output periods (" +
               number_text((kMeasuredCurveMinRows - 1) / s.output_rate_hz) + " s)");
  const double samples = recorded_sample_count(s.duration_s, s.output_rate_hz);
  std::string problem = recording_size_problem(samples, kTrajectoryBytesPerSample);
  if (const MemoryLimit memory = process_memory_limit(); problem.empty() && memory.bytes < kMaxRecordingBytes)
    problem = recording_size_problem(samples, kTrajectoryBytesPerSample, memory.bytes, memory.what);
  if (!problem.empty())
    r.fail(r.has("duration") ? "duration" : "travel_distance",
           problem + " at " + number_text(s.output_rate_hz) + " Hz; reduce duration or output_rate");
}

// A wheel deep in the ground would start with a contact force far beyond
// the rover's weight: a typo in z, not a drop test.
void refuse_deep_start(const JsonReader& r, const ScenarioSetup& setup) {
  const WheelPenetration start = deepest_wheel_penetration(setup.model, setup.scenario.initial_q);
  if (const double tolerance = initial_penetration_tolerance_m(setup.model); start.depth_m > tolerance) {
    char depth[160];
    std::snprintf(depth, sizeof depth,
                  "wheel %s starts %.4g m below the ground (tolerance %.3g m, the depth at which "
                  "one wheel carries the rover's weight)",
                  kWheelNames[static_cast<std::size_t>(start.leg)], start.depth_m, tolerance);
    if (r.has("initial_ground_clearance"))
      r.fail("initial_ground_clearance", std::string(depth) + "; raise it (it is measured from z = 0, "
                                         "not from the terrain under the wheels)");
    r.fail("initial_q", std::string(depth) + "; raise initial_q.z or give initial_ground_clearance");
  }
}

// The height of the lowest wheel's rim above the terrain under its centre
// (centre height less the radius: never more than the true clearance); 0 or
// less when a wheel touches.
double lowest_wheel_clearance_m(const RoverModel& model, const Coordinates& q) {
  const TreeKinematics kin = forward_kinematics(model.tree, q, Coordinates::Zero());
  double lowest_m = std::numeric_limits<double>::infinity();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec3& centre = kin.nodes[node::wheel(leg)].origin;
    lowest_m = std::min(lowest_m, centre.z() - model.parameters.geometry.wheel_radius_m -
                                      model.terrain.height(centre.x(), centre.y()));
  }
  return lowest_m;
}

// A start that lands faster than kMaxDriveSpeed_mps (a drop from metres, a
// height in millimetres): the wheels would go through the ground, as no
// Kelvin-Voigt contact of this stiffness holds such an impact.
void refuse_impact_beyond_scale(const JsonReader& r, const ScenarioSetup& setup) {
  const double clearance_m = std::max(0.0, lowest_wheel_clearance_m(setup.model, setup.scenario.initial_q));
  const double falling_mps = setup.scenario.initial_u[coord::z];
  const double impact_mps =
      std::sqrt(falling_mps * falling_mps + 2.0 * setup.model.parameters.gravity_mps2 * clearance_m);
  if (!(impact_mps > kMaxDriveSpeed_mps)) return;
  r.fail(r.has("initial_ground_clearance") ? "initial_ground_clearance" : "initial_q",
         "the lowest wheel starts " + number_text(clearance_m) + " m above the ground at z speed " +
             number_text(falling_mps) + " m/s and lands at " + number_text(impact_mps) + " m/s, beyond +-" +
             number_text(kMaxDriveSpeed_mps) + " m/s: the wheels would go through the ground (the paper's drops "
             "land at under 1 m/s); a height in millimetres?");
}

}  // namespace

ScenarioSetup build_scenario(const ScenarioSources& sources) {
  const std::string& path = sources.scenario_path;
  const JsonReader r(sources.scenario, path);
  ScenarioSetup setup;
  setup.scenario_path = path;
  Scenario& s = setup.scenario;
  s.name = r.string_or("name", std::filesystem::path(path).stem().string());
  if (r.has("name") && !is_plain_file_name(s.name))
    r.fail("name", "must be a plain file name, with no '/', '\\' or control character (rover simulate writes "
           "results/<name>.h5 by default)");
  r.string_or("description", "");
  r.string("rover");
  if (r.has("terrain")) r.string("terrain");
  setup.rover_path = sources.rover_path;
  setup.terrain_path = sources.terrain_path;
  setup.files = sources.files;
  setup.model = make_checked_rover_model(parse_rover_parameters(sources.rover, sources.rover_path),
                                        sources.terrain, sources.rover_path);
  parse_initial_state(r, sources, setup);
  parse_run_length(r, s);
  const bool has_drive = r.has("drive");
  if (has_drive) {
    refuse_segments_after_the_end(r.child("drive"), s);
    refuse_ramp_beyond_the_end(r.child("drive"), s);
  }
  refuse_runs_beside_the_grid(r, setup);
  if (r.has("integrator")) s.integrator = parse_integrator_settings(r.child("integrator"), s.integrator);
  if (r.has("wall_time_budget")) s.wall_time_budget_s = r.positive("wall_time_budget");
  if (std::string why; !scenario_is_valid(s, &why)) r.fail("integrator", why);
  refuse_deep_start(r, setup);
  refuse_impact_beyond_scale(r, setup);
  setup.inputs = nominal_inputs(setup.model.parameters);
  if (r.has("inputs")) setup.inputs = parse_simulation_inputs(r.child("inputs"), setup.inputs);
  r.finish();
  return setup;
}

}  // namespace rover::io
