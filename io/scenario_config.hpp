// Scenario files (configs/scenarios/*.json, docs/model.md §7).
//
// {
//   "name": "drop_horizontal",
//   "description": "free text",
//   "rover": "../rover.json",                 // relative to this file
//   "terrain": "../terrains/flat.json",       // optional, default flat z = 0
//   "duration": 1.0,                          // s; or "travel_distance" [m] with "forward_speed"
//   "forward_speed": 1.0,                     // optional [m/s]: dx/dt = v, every dzj/dt = w_ref = v / R_w
//   "travel_distance": 2.869,                 // optional [m]: duration = distance / forward_speed
//   "initial_ground_clearance": 0.001,        // optional [m]: z so the lowest wheel bottom is this high
//   "initial_q": {"z": 0.281, "chi": 0.039},  // by docs/model.md names: x y z theta chi psi phi b11 .. z4
//   "initial_u": {"x": 1.0},
//   "wheel_speed_ref": [0, 0, 0, 0],          // rad/s (overrides forward_speed's)
//   "steer_ref": [0, 0, 0, 0],                // rad
//   "output_rate": 1000,                      // Hz
//   "integrator": {"method": "dopri5" | "rk4" | "rosenbrock", "rtol": 1e-6, "atol": 1e-9,
//                  "initial_step": 1e-5, "min_step": 1e-12, "max_step": 0.01, "fixed_step": 1e-5},
//                                             // a method other than the base's starts from its
//                                             // own default tolerances (default_integrator_settings)
//   "wall_time_budget": 3600,                 // s; a longer run stops with a status
//   "inputs": {"f": 1e4, "c_q": 0.14, "M0": [8]},  // optional overrides of the rover config
//   "drive": {...}                            // optional, see below
// }
//
// "drive": a time-varying driving command (core/drive_kinematics.hpp),
// turned into the steering and wheel-speed references d_ref, w_ref at every
// time by the simulator. It replaces "forward_speed", "wheel_speed_ref" and
// "steer_ref" (giving one of them too is an error), and needs "duration".
//
// "drive": {
//   "ramp_time": 0.3,              // optional [s], default 0: smoothstep blend at each
//                                  // segment start after the first (0 = steps)
//   "allow_flip": true,            // optional: serve headings beyond the end-stop by
//                                  // turning the wheel by pi and reversing it
//   "initial_motion": "commanded", // optional: "commanded" (default) or "rest"
//   "segments": [                  // piecewise-constant commands, start times increasing
//     {"start": 0.0, "mode": "ackermann", "speed": 0.3, "radius": 1.0},
//     {"start": 5.0, "mode": "general-ackermann", "forward": 0.2, "lateral": 0.1, "yaw_rate": 0.3}
//   ]
// }
//
// A segment runs from "start" [s] until the next one starts; the first starts
// at 0 ("start" may be left out there), each later one lasts at least
// ramp_time. "mode" is one of car, ackermann, general-ackermann, parallel,
// lateral, rotation. The command is given in one of two forms:
//   * the chassis velocity at G in chassis axes: "forward" [m/s], "lateral"
//     [m/s, + left], "yaw_rate" [rad/s, + turning left], each defaulting to 0.
//     The mode must be able to serve it (e.g. parallel: yaw_rate 0; car: the
//     rear-axle centre moves straight ahead); rotation takes "yaw_rate" only.
//   * the mode's natural parameters, "speed" [m/s, signed, + forward] with
//       car, ackermann:    "radius" [m, signed, + = turning left; omit for
//                          straight ahead] of the rear-axle centre (car) or of
//                          the point midway between the axles (ackermann; G on
//                          the default rover), which moves at "speed";
//       general-ackermann: "icr": [x, y] [m], the instantaneous centre of
//                          rotation in the chassis frame; G moves at "speed";
//       parallel:          "crab_angle" [rad, + left of forward], default 0;
//       lateral:           nothing else (+ = left).
//     These are turned into the equivalent body velocity; a zero speed is rest
//     (the wheels hold their steering).
// A segment the mode cannot serve, a steering angle beyond the end-stop that
// the flip cannot serve, or a bad schedule is a ConfigError naming the file
// and the field ("drive.segments[1]").
//
// Initial state with a drive: the initial steering angles d_j are the
// commanded ones at t = 0. With "initial_motion": "commanded" the chassis
// starts with the commanded body velocity at t = 0 (turned into the world
// frame by the initial yaw theta: dx/dt, dy/dt, dtheta/dt = yaw_rate) and every
// wheel spins at its commanded rate dz_j/dt, so a rover dropped from
// "initial_ground_clearance" lands already rolling; with "rest" every speed
// starts at 0 (begin the schedule with a zero-speed segment and a ramp_time
// to accelerate smoothly). Entries of "initial_q" and "initial_u" override
// these values.
//
// Validation at load, besides the ranges of each field:
//   * the recording must fit in memory: duration x output_rate samples of
//     kTrajectoryBytesPerSample each, at most kMaxRecordingBytes, so an absurd
//     request ("duration": 1e12) is refused with its size instead of failing
//     in the allocator;
//   * no wheel may start deeper in the terrain than
//     initial_penetration_tolerance_m(): beyond it the first contact force
//     would be larger than the rover's weight carried by one wheel, a start
//     in the ground rather than on it. Starting high above it is allowed.
#pragma once

#include <string>

#include "core/coordinates.hpp"
#include "core/rover_model.hpp"
#include "core/scenario.hpp"
#include "core/simulate.hpp"
#include "io/json_reader.hpp"

namespace rover::io {

struct ScenarioSetup {
  Scenario scenario;
  RoverModel model;
  ModelInputs inputs;  // rover config defaults with the scenario's overrides
  std::string scenario_path, rover_path, terrain_path;
};

ScenarioSetup load_scenario(const std::string& path);

// The files a scenario is made of, read once: its JSON, the rover JSON it
// names and the terrain. A study varies the two JSON documents in memory and
// builds the scenario of each run from them (build_scenario), so every sample
// passes the same validation as a file would, without touching the disk; the
// terrain grid is shared, not copied.
struct ScenarioSources {
  Json scenario, rover;
  std::string scenario_path, rover_path, terrain_path;  // for messages and provenance
  Terrain terrain = Terrain::flat();
};
ScenarioSources read_scenario_sources(const std::string& path);
// load_scenario(path) == build_scenario(read_scenario_sources(path)).
// Throws ConfigError naming the file (scenario or rover) and the field.
ScenarioSetup build_scenario(const ScenarioSources& sources);

// Bytes a Trajectory holds per output sample: t, B_l_z, B_r_z, G_z, pitch,
// roll, q and u (23 each) and the 4 normal forces, as doubles.
inline constexpr double kTrajectoryBytesPerSample = 8.0 * (6 + 2 * kNumCoordinates + kNumLegs);
// The largest recording a run may ask for (8 GiB).
inline constexpr double kMaxRecordingBytes = 8.0 * 1024.0 * 1024.0 * 1024.0;

// The number of output samples over [0, duration_s] at rate_hz (as
// output_sample_count), in floating point so absurd requests do not overflow.
double recorded_sample_count(double duration_s, double rate_hz);

// Empty when `samples` of `bytes_per_sample` fit in `max_bytes`; otherwise
// "would record 1.0e+15 samples (448 PB, more than the 8.59 GB allowed)" for
// the caller to extend with the remedy.
std::string recording_size_problem(double samples, double bytes_per_sample,
                                   double max_bytes = kMaxRecordingBytes);

// Deepest start of a wheel in the terrain that load_scenario accepts: the
// penetration at which the contact law k_g p^sigma carries the whole weight
// of the rover on one wheel, and at least 1 mm.
double initial_penetration_tolerance_m(const RoverModel& model);

// The deepest penetration of any wheel into the terrain at pose q (0 if all
// are clear), and which wheel (0..3; -1 if none touches).
struct WheelPenetration {
  double depth_m = 0.0;
  int leg = -1;
};
WheelPenetration deepest_wheel_penetration(const RoverModel& model, const Coordinates& q);

// The "drive" block (see above) for a rover with these driving kinematics.
struct DriveConfig {
  DriveSchedule schedule;
  WheelCommands commands_at_start;  // the compiled schedule's commands at t = 0
  bool start_at_rest = false;       // "initial_motion": "rest"
};
DriveConfig parse_drive(const JsonReader& r, const DriveKinematics& kinematics);

// Parses "integrator": {...} over `base`; used by scenarios and studies.
IntegratorSettings parse_integrator_settings(const JsonReader& r, IntegratorSettings base);

// Parses {"f", "c_q", "M0": [8]} over `base`.
ModelInputs parse_simulation_inputs(const JsonReader& r, ModelInputs base);

// Resolves a path written in a config file relative to that file's directory.
std::string resolve_relative(const std::string& config_path, const std::string& path);

}  // namespace rover::io
