#include "study/studies/study_config.hpp"


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
  if (r.has("integrator"))
    c.setup.scenario.integrator =
        io::parse_integrator_settings(r.child("integrator"), c.setup.scenario.integrator);
  c.fingerprint = io::config_fingerprint(read_text(c.path) + read_text(scenario) +
                                         read_text(c.setup.rover_path) +
                                         read_text(c.setup.terrain_path));
  return c;
}

std::string results_path(const StudyCommon& common, const std::string& requested) {
  return requested.empty() ? "results/" + common.name + ".h5" : requested;
}

}  // namespace rover::study
