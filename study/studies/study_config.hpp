// The common keys of a calibration study file (the other studies read theirs
// into a StudySpec, study_spec.hpp), and the study's integrator block:
//   "type": "calibration",
//   "name": "...", "description": "...",
//   "scenario": "../scenarios/drop_horizontal.json"  (relative to the study file),
//   "integrator": {"method": "dopri5", "rtol": .., ...}  (optional override of the scenario's)
// The fingerprint covers the study, scenario, rover and terrain files, so a
// checkpoint is never resumed against a changed configuration.
#pragma once

#include <optional>
#include <string>

#include "io/hdf5_file.hpp"
#include "io/json_reader.hpp"
#include "io/scenario_config.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::study {

// used by calibration until it moves to the study driver (study_driver.hpp):
// the run options with calibration's on/off plot switch.
struct StudyRunControl : StudyRunOptions {
  bool plot = true;
};

// used by calibration until it moves to the study driver; the other studies
// read their common keys into a StudySpec (study_spec.hpp).
struct StudyCommon {
  std::string path, name, type;
  io::ScenarioSetup setup;
  std::string fingerprint;
  std::string accuracy_choice;  // what "accuracy" chose ("rosenbrock rtol 1e-05 atol 1e-08"), if given
};

// The study's integrator: its "integrator" block applied to `base`, or the
// setting integrator_for_accuracy (core/accuracy_choice.hpp) chooses for its
// "accuracy" [m], in (1e-12, 1e-2); std::nullopt when it gives neither. Both
// at once, or an accuracy outside the range, is a ConfigError naming the
// field. `choice` (if not null) receives the chosen setting's description.
std::optional<IntegratorSettings> study_integrator(const io::JsonReader& reader, const IntegratorSettings& base,
                                                   std::string* choice = nullptr);

// Reads the common keys (and marks them used in `reader`); checks the type.
StudyCommon parse_study_common(const io::JsonReader& reader, const std::string& expected_type);

// The text of a file (for fingerprints and provenance attributes).
std::string read_text(const std::string& path);

// The attributes on "/" that every study result carries: study (its type),
// name, study_file, study_json (the file's text), integrator, rtol, atol,
// ranks, fingerprint, project_version.
void write_study_provenance(io::Hdf5Writer& h5, const StudyCommon& common);

// used by calibration until it moves to the study driver, which checks the
// path with checked_results_path() (study_output.hpp). Where a study writes:
// the path the user asked for, or results/<name>.h5 if that is empty.
std::string results_path(const StudyCommon& common, const std::string& requested);

}  // namespace rover::study
