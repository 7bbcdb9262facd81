// The numeric parameters a study may vary, named by dotted paths that mirror
// the config files: any number of the rover file ("contact.k_g",
// "bodies.chassis.mass", "geometry.wheel_radius", "s_structure.preload_mean[3]")
// and of the scenario file, prefixed "scenario." ("scenario.initial_q.z",
// "scenario.forward_speed"). docs/model.md §5 gives the paper's short names,
// kept as aliases: "f", "c_q", "M0_11" ... "M0_42" (also "s_structure.M0_11"),
// which address s_structure.f, s_structure.c_q and s_structure.preload_mean[i],
// and "M0_scale", which addresses s_structure.preload_scale: a factor (nominal
// 1) on all eight preloads, applied to the values the documents hold when it
// is applied (so after any single preload set before it).
//
// Values are applied to copies of the two JSON documents (apply()), and the
// run's scenario is built from them by io::build_scenario(), so a sample goes
// through exactly the validation a config file does: a negative mass or
// preload is rejected with the loader's message, never run silently.
//
// A scenario's "inputs" block ({"f", "c_q", "M0"}) overrides the rover file;
// f, c_q and the preloads are applied to both, so the value set is the value
// simulated.
#pragma once

#include <string>
#include <vector>

#include "io/json_reader.hpp"

namespace rover::study {

class ParameterSpace {
 public:
  // `rover` and `scenario` are the JSON documents of a scenario's sources.
  ParameterSpace(const io::Json& rover, const io::Json& scenario);

  // The canonical name of `name_or_alias`; throws std::invalid_argument
  // naming the closest valid names and listing them all.
  std::string canonical(const std::string& name_or_alias) const;
  bool contains(const std::string& name_or_alias) const;
  // The configured (effective) value of a canonical name; NaN for an optional
  // scenario key that the scenario does not set.
  double nominal(const std::string& canonical_name) const;
  // Sets the value in the documents (creating an optional scenario key).
  void apply(const std::string& canonical_name, double value, io::Json& rover,
             io::Json& scenario) const;

  // Every canonical name, sorted, and the aliases.
  const std::vector<std::string>& names() const { return names_; }
  std::vector<std::string> aliases() const;

 private:
  std::vector<std::string> names_;
  const io::Json* rover_;
  const io::Json* scenario_;
};

// The alias of a preload index 0..7: "M0_11", "M0_12", ..., "M0_42".
std::string preload_alias(int index);

// Why the canonical name is a setting of the runs and no property of the
// rover or the scenario ("scenario.wall_time_budget", the wall-time limit of
// a run), so that it cannot be an uncertain input of a study or a fitted
// parameter: nothing it varies is physics (a design `evaluate` runs may still
// set it per row). Empty for every other name.
std::string run_setting_not_parameter(const std::string& canonical_name);

// Whether the canonical names `a` and `b` set a common number of the rover:
// the same name, or the preloads' common factor (M0_scale) and one of the
// preloads it multiplies. Two such inputs of one run would make it depend on
// the order they are applied in, so every place that combines parameters
// (a study's "parameters", a design's columns, a calibration's fit, a
// candidate's "set") refuses them.
bool parameters_overlap(const std::string& a, const std::string& b);
// Why two distinct overlapping names overlap, for messages ("M0_scale
// multiplies all eight preloads, M0_11 among them, ..."); "" if they do not.
std::string overlap_reason(const std::string& a, const std::string& b);

}  // namespace rover::study
