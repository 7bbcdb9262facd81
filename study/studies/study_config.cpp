#include "study/studies/study_config.hpp"

#include "core/accuracy_choice.hpp"


#include "io/checkpoint.hpp"
#include "study/studies/study_output.hpp"
#include "study/runtime/study_runner.hpp"

namespace rover::study {

std::string read_text(const std::string& path) { return file_text(path); }

void write_study_provenance(io::Hdf5Writer& h5, const StudyCommon& common) {
  write_base_provenance(h5, common.type, common.name, common.path, &common.setup.scenario.integrator,
                        common.fingerprint);
}

StudyCommon parse_study_common(const io::JsonReader& r, const std::string& expected_type) {
  StudyCommon c;
  c.path = r.file();
  c.type = r.string("type");
  if (c.type != expected_type)
    r.fail("type", "this command runs '" + expected_type + "' studies");
  c.name = r.string("name");
  r.string_or("description", "");
  const std::string scenario = io::resolve_relative(c.path, r.string("scenario"));
  try {
    c.setup = io::load_scenario(scenario);
  } catch (const io::ConfigError& e) {
    r.fail("scenario", e.what());
  }
  if (const auto integrator = study_integrator(r, c.setup.scenario.integrator, &c.accuracy_choice))
    c.setup.scenario.integrator = *integrator;
  c.fingerprint = io::config_fingerprint(read_text(c.path) + read_text(scenario) +
                                         read_text(c.setup.rover_path) +
                                         read_text(c.setup.terrain_path));
  return c;
}

std::optional<IntegratorSettings> study_integrator(const io::JsonReader& r, const IntegratorSettings& base,
                                                   std::string* choice) {
  if (r.has("integrator") && r.has("accuracy"))
    r.fail("accuracy", "give either \"accuracy\" or \"integrator\", not both");
  if (r.has("integrator")) return io::parse_integrator_settings(r.child("integrator"), base);
  if (!r.has("accuracy")) return std::nullopt;
  try {
    const IntegratorChoice chosen = integrator_for_accuracy(r.number("accuracy"));
    if (choice != nullptr) *choice = chosen.description;
    return chosen.settings;
  } catch (const std::invalid_argument& e) {
    r.fail("accuracy", e.what());
  }
  return std::nullopt;
}

std::string results_path(const StudyCommon& common, const std::string& requested) {
  return requested.empty() ? "results/" + common.name + ".h5" : requested;
}

}  // namespace rover::study
