// Scenario files (configs/scenarios/*.json, MODEL.md section 7).
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
//   "initial_q": {"z": 0.281, "chi": 0.039},  // by MODEL.md names: x y z theta chi psi phi b11 .. z4
//   "initial_u": {"x": 1.0},
//   "wheel_speed_ref": [0, 0, 0, 0],          // rad/s (overrides forward_speed's)
//   "steer_ref": [0, 0, 0, 0],                // rad
//   "output_rate": 1000,                      // Hz
//   "integrator": {"method": "dopri5" | "rk4", "rtol": 1e-6, "atol": 1e-9,
//                  "initial_step": 1e-5, "min_step": 1e-12, "max_step": 0.01, "fixed_step": 1e-5},
//   "wall_time_budget": 3600,                 // s; a longer run stops with a status
//   "inputs": {"f": 1e4, "c_q": 0.14, "M0": [8]}  // optional overrides of the rover config
// }
#pragma once

#include <string>

#include "core/rover_model.hpp"
#include "core/scenario.hpp"
#include "core/simulate.hpp"
#include "io/json_reader.hpp"

namespace rover::io {

struct ScenarioSetup {
  Scenario scenario;
  RoverModel model;
  SimulationInputs inputs;  // rover config defaults with the scenario's overrides
  std::string scenario_path, rover_path, terrain_path;
};

ScenarioSetup load_scenario(const std::string& path);

// Parses "integrator": {...} over `base`; used by scenarios and studies.
IntegratorSettings parse_integrator_settings(const JsonReader& r, IntegratorSettings base);

// Parses {"f", "c_q", "M0": [8]} over `base`.
SimulationInputs parse_simulation_inputs(const JsonReader& r, SimulationInputs base);

// Resolves a path written in a config file relative to that file's directory.
std::string resolve_relative(const std::string& config_path, const std::string& path);

}  // namespace rover::io
