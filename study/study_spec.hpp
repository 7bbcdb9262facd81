// The part of a study file every design-based study shares (montecarlo,
// evaluate, sensitivity, and the calibration priors):
//
//   "type": "montecarlo", "name": "preload_mc", "description": "...",
//   "scenario": "../scenarios/drop_horizontal.json"     (the rover; or)
//   "model": "ishigami" | "sobol_g" | "linear"          (an analytic test model)
//   "integrator": {"method": "rosenbrock", ...}         (optional, replaces the scenario's)
//   "parameters": {                                     (the uncertain inputs)
//     "c_q": {"distribution": "uniform", "min": 0.05, "max": 0.40},
//     "f":   {"distribution": "log_uniform", "min": 1e2, "max": 1e5},
//     "M0":  {"distribution": "normal", "from_config": true, "sd_scale": 1.0},
//     "contact.k_g": {"distribution": "normal", "sd_percent": 10}
//   },
//   "design": {"type": "monte_carlo" | "latin_hypercube" | "sobol" | "grid",
//              "samples": 1024, "seed": 7, "levels": 5 | {"c_q": 3, "f": 4}},
//   "qoi": ["B_l_z_min", "deflection", {"name": "settling_time", "band": 0.001},
//           {"name": "rms_vs", "reference": "../data/x.csv", "time_offset": 0.05,
//            "channel": "B_l_z", "label": "rms_drop"}],
//   "channels": ["B_l_z", "G_z"]
//
// Parameter names: study/parameter_space.hpp. Distributions:
// study/distributions.hpp. "from_config" (the preloads "M0" or one "M0_jk"):
// Normal(preload_mean, sd_scale * preload_sd) of the rover file. Inputs are
// independent. A sample outside a parameter's valid range is recorded as
// rejected with the loader's reason; "truncate" keeps samples inside.
// Analytic models have inputs x1 .. xd with their textbook distributions
// (ishigami: U(-pi, pi); sobol_g: U(0, 1); linear: N(0, 1)); "parameters" may
// replace them.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/json_reader.hpp"
#include "study/design.hpp"
#include "study/distributions.hpp"
#include "study/study_model.hpp"

namespace rover::study {

struct UncertainInput {
  std::string name;   // canonical parameter name (or x1 .. xd)
  std::string label;  // as the study file wrote it, aliases kept ("c_q", "M0_11")
  Distribution distribution;
  double nominal = 0.0;
};

struct DesignSpec {
  DesignType type = DesignType::kMonteCarlo;
  int samples = 0;
  std::uint64_t seed = 1;
  std::vector<int> grid_levels;  // per input (1 for fixed ones), grid only
};

struct StudySpec {
  std::string path, type, name, description;
  std::string fingerprint;  // every file that changes a result, and the options
  std::shared_ptr<const StudyModel> model;
  std::shared_ptr<const RoverStudyModel> rover;  // null for an analytic model
  std::vector<UncertainInput> inputs;
  DesignSpec design;
};

// Reads the keys above and marks them used; the caller reads its own keys,
// then calls r.finish(). Errors name the study file and the field. With
// kByCaller the "design" key is left to the caller (sensitivity designs).
enum class DesignKey { kRequired, kByCaller };
StudySpec parse_study_spec(const io::JsonReader& r, const std::vector<std::string>& types,
                           DesignKey design = DesignKey::kRequired);

// The design in physical units: samples x inputs (fixed inputs are constant
// columns). Row i depends only on the seed and i (LHS: on the seed).
DesignMatrix study_design(const StudySpec& spec);

// Labels of the inputs, in order (for /inputs/names and CSV headers).
std::vector<std::string> input_labels(const StudySpec& spec);

// The text of a file ("" if unreadable), for fingerprints and provenance.
std::string file_text(const std::string& path);

// Adds text (an option value, a data file's contents) to a fingerprint.
std::string extend_fingerprint(const std::string& fingerprint, const std::string& text);

}  // namespace rover::study
