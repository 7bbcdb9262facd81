// Scenario files (configs/scenarios/*.json, docs/model.md §7): loading,
// validation, and building a scenario from in-memory JSON for studies.
// The file format (every key, its unit and default, and the "drive" block) is
// documented in one place: docs/configuration.md, "Scenario files".
#pragma once

#include <string>

#include "core/coordinates.hpp"
#include "core/rover_model.hpp"
#include "core/scenario.hpp"
#include "core/simulate.hpp"
#include "io/input_files.hpp"
#include "io/json_reader.hpp"

namespace rover::io {

struct ScenarioSetup {
  Scenario scenario;
  RoverModel model;
  ModelInputs inputs;  // rover config defaults with the scenario's overrides
  std::string scenario_path, rover_path, terrain_path;
  InputFiles files;  // the files the scenario names (scenario_files)
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
  InputFiles files;  // the files the scenario names (scenario_files)
};
ScenarioSources read_scenario_sources(const std::string& path);

// The files a scenario names, so that no output replaces them: its rover
// ("'rover' in <scenario>") and terrain ("'terrain' in <scenario>"); the
// scenario file itself is named by whoever names it (a flag, a study field).
InputFiles scenario_files(const ScenarioSources& sources);
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
// "would record 1.0e+15 samples (448 PB, more than the 8.59 GB allowed)", or
// "... more than the 0.7 GB of <limit_name>)" when the bound is a limit of
// the process (io/process_memory.hpp), for the caller to extend with the remedy.
std::string recording_size_problem(double samples, double bytes_per_sample,
                                   double max_bytes = kMaxRecordingBytes, const std::string& limit_name = "");

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

// What is wrong with the angles of pose q ("b12 = 100 rad is beyond ..."):
// a chassis pitch or roll (chi, psi) or a bogie angle (phi) beyond a quarter
// turn, a heading (theta) or a wheel's rolling angle (z1 .. z4) beyond a full
// turn, an S-structure deflection beyond kMaxSStructureDeflection_rad or a
// steering angle beyond the end-stop; "" when nothing is.
std::string pose_angle_problem(const RoverModel& model, const Coordinates& q);

// The "drive" block (see above) for a rover with these driving kinematics.
struct DriveConfig {
  DriveSchedule schedule;
  WheelCommands commands_at_start;  // the compiled schedule's commands at t = 0
  bool start_at_rest = false;       // "initial_motion": "rest"
};
DriveConfig parse_drive(const JsonReader& r, const DriveKinematics& kinematics);

// The scale of a state's speeds (a scenario's initial_u and wheel_speed_ref,
// an `rover eom` state), as core/model_scale.hpp bounds the commanded ones:
// x, y and z within kMaxDriveSpeed_mps; the chassis's angular rates (theta,
// chi, psi) within the rate that would move the rover's farthest point at
// that speed, kMaxDriveSpeed_mps / rover_extent_m (about 26 rad/s); every
// other rate (a wheel's spin, a joint's) within the rate that would move a
// wheel rim at that speed, kMaxDriveSpeed_mps / wheel radius (118 rad/s for
// 8.5 cm wheels). Empty when `value`, the speed of coordinate `index`, is
// within; otherwise "1e+04 rad/s is beyond +-117.647 rad/s, ...".
struct SpeedScale {
  double wheel_radius_m = 0.0;
  double rover_extent_m = 0.0;  // from G to the farthest wheel rim, in the zero pose
};
SpeedScale speed_scale(const RoverModel& model);
double max_rate_radps(double wheel_radius_m);
std::string rate_beyond_scale(double rate_radps, double wheel_radius_m);
std::string speed_beyond_scale(int index, double value, const SpeedScale& scale);

// Parses "integrator": {...} over `base`; used by scenarios and studies.
IntegratorSettings parse_integrator_settings(const JsonReader& r, IntegratorSettings base);

// Parses {"f", "c_q", "M0": [8]} over `base`.
ModelInputs parse_simulation_inputs(const JsonReader& r, ModelInputs base);

// Resolves a path written in a config file relative to that file's directory,
// as the operating system does: "lnk/../rover.json" through a linked folder
// `lnk` names the rover.json beside the link's target. The name is written
// without "." and ".." where that names the same file (the common case).
std::string resolve_relative(const std::string& config_path, const std::string& path);

// The file named by the string field `key` of `r`, resolved relative to r's
// file; a name that reaches no readable file is refused naming the config,
// the field and the path resolved: "s.json: field 'data' (value "d.csv"):
// file not found: cfg/d.csv". `kind`: "a JSON file", "a CSV file".
std::string named_input_file(const JsonReader& r, const std::string& key, const std::string& kind);

}  // namespace rover::io
