#include "study/study_config.hpp"

#include <fstream>
#include <sstream>

#include "io/checkpoint.hpp"
#include "study/study_runner.hpp"

namespace rover::study {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_study_provenance(io::Hdf5Writer& h5, const StudyCommon& common) {
  const IntegratorSettings& integrator = common.setup.scenario.integrator;
  h5.attribute("/", "study", common.type);
  h5.attribute("/", "name", common.name);
  h5.attribute("/", "study_file", common.path);
  h5.attribute("/", "study_json", read_text(common.path));
  h5.attribute("/", "integrator", integrator_name(integrator.method));
  h5.attribute("/", "rtol", integrator.relative_tolerance);
  h5.attribute("/", "atol", integrator.absolute_tolerance);
  h5.attribute("/", "ranks", static_cast<long long>(world_size()));
  h5.attribute("/", "fingerprint", common.fingerprint);
  h5.attribute("/", "project_version", ROVER_VERSION);
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
