// The part of a study file every design-based study shares (montecarlo,
// evaluate, sensitivity, calibration priors): the model (a scenario or an
// analytic test model), the uncertain parameters and their distributions, the
// design, the QoIs and the channels. The file format is documented in one
// place: docs/configuration.md, "Study files". Parameter names:
// study/model/parameter_space.hpp; distributions: study/estimators/distributions.hpp; QoIs:
// study/model/qoi.hpp (formulas and units).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/input_files.hpp"
#include "io/json_reader.hpp"
#include "study/design/design.hpp"
#include "study/estimators/distributions.hpp"
#include "study/model/study_model.hpp"

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
  // The files the study file names: its scenario and what that names, the
  // reference curves (not the study file itself: the command names it).
  io::InputFiles files;
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
