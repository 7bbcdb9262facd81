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
#include <optional>
#include <string>
#include <vector>

#include "core/scenario.hpp"
#include "io/checkpoint.hpp"
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

// The study's integrator for runs of `scenario`: its "integrator" block
// (applied to the defaults of the method it names, else to the scenario's
// settings), or the setting integrator_for_accuracy (core/accuracy_choice.hpp)
// chooses for its "accuracy" [m], in (1e-12, 1e-2); std::nullopt when it
// gives neither. Both at once, an accuracy outside the range, or settings the
// scenario cannot run with (an rk4 step that does not divide its output
// period) is a ConfigError naming the field. `choice` (if not null) receives
// the chosen setting's description.
std::optional<IntegratorSettings> study_integrator(const io::JsonReader& reader, const Scenario& scenario,
                                                   std::string* choice = nullptr);
// Refuses, naming `field`, integrator settings `scenario` cannot run with
// (scenario_is_valid with them in place of its own).
void refuse_integrator_the_scenario_refuses(const io::JsonReader& reader, const std::string& field,
                                            const Scenario& scenario, const IntegratorSettings& integrator);

// What names a study file: its path, "type", "name" and "description".
struct StudyIdentity {
  std::string path, type, name, description;
};

// Reads "type" (one of `types`), "name" (a plain file name: results go to
// results/<name>.h5) and "description"; errors name the file and the field.
StudyIdentity parse_study_identity(const io::JsonReader& r, const std::vector<std::string>& types);
// `fingerprint` with the setting "study", "<type> '<name>'": a checkpoint of
// another study at the same --out is named as such.
std::string with_study_identity(const std::string& fingerprint, const StudyIdentity& identity);

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
  // Distribution tails the model refuses, with the share of samples they
  // hold: those runs will fail. Printed before the runs, written as the
  // attribute input_warnings.
  std::vector<std::string> warnings;
  std::string accuracy_choice;  // the setting "accuracy" chose, in words (empty without "accuracy")
  double refused_share = 0.0;  // of the samples, in those tails (inputs drawn independently)
};

// Reads the keys above and marks them used; the caller reads its own keys,
// then calls r.finish(). Errors name the study file and the field. With
// kByCaller the "design" key is left to the caller (sensitivity designs);
// `min_samples` is the fewest "design.samples" the study accepts (named
// in the message for a count that is none).
enum class DesignKey { kRequired, kByCaller };
StudySpec parse_study_spec(const io::JsonReader& r, const std::vector<std::string>& types,
                           DesignKey design = DesignKey::kRequired, int min_samples = 1);

// The design in physical units: samples x inputs (fixed inputs are constant
// columns). Row i depends only on the seed and i (LHS: on the seed).
DesignMatrix study_design(const StudySpec& spec);
// The spec's warnings about its inputs, and one when a Sobol' design's size
// is not a power of two (the sequence is balanced at 2^k points): read at
// the run, after any --samples override.
std::vector<std::string> design_warnings(const StudySpec& spec);
// The warning for `n` Sobol' `points` ("points", "base points") that are not
// a power of two, where the sequence is balanced; empty when n is one.
std::string sobol_balance_warning(std::uint64_t n, const std::string& points);

// Labels of the inputs, in order (for /inputs/names and CSV headers).
std::vector<std::string> input_labels(const StudySpec& spec);

// A warning for QoI `q` (the study's order) whose values over the runs
// (`values`, NaN for a failed one) do not mean what their name says:
//  * a settling_time where some runs had not settled (B_l z still outside
//    its band at the end): the value is the run's end, not a settling time;
//  * an rms_vs where every run misses the reference by more than the span of
//    its heights: the run never comes near it (heights not in metres, another
//    channel).
// Empty otherwise (and for an analytic model).
std::string qoi_values_warning(const StudySpec& spec, std::size_t q, const std::vector<double>& values);
// The same for QoI `q` of a rover model (evaluate's rows).
std::string qoi_values_warning(const RoverStudyModel& model, std::size_t q, const std::vector<double>& values);

// The text of a file ("" if unreadable), for fingerprints and provenance.
std::string file_text(const std::string& path);

// Adds text (a data file's contents) to a fingerprint: the key of a study's
// runs (io/checkpoint.hpp run keys: a digest, then the settings in force).
std::string extend_fingerprint(const std::string& fingerprint, const std::string& text);

// The keys of a study file that only its analysis reads, never its runs: a
// checkpoint's runs serve whatever they say (raise max_failed_fraction, and
// --resume reuses the runs).
inline constexpr const char* kAnalysisOnlyKeys[] = {"max_failed_fraction", "bootstrap", "confidence", "estimator"};

// The study file's content that its runs depend on, for their key: the JSON
// without kAnalysisOnlyKeys (its layout and spaces do not count).
std::string study_file_run_text(const io::Json& study);

// The flags that override a study file's design: its size and its seed. Each
// loader applies them before it checks the design, so a file's size too small
// for the study is no error when --samples replaces it; an overriding value
// the study cannot take is refused naming the flag.
struct DesignOverrides {
  std::optional<long long> samples;
  std::optional<std::uint64_t> seed;
};

// The key `fingerprint` with the setting `flag` = `value` added (from the
// flag when `from_flag`, else from the input file `origin`).
std::string with_setting(const std::string& fingerprint, const std::string& flag, const std::string& value,
                         bool from_flag, const std::string& origin = io::RunSetting{}.origin);

}  // namespace rover::study
