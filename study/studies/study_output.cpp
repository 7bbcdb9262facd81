// See study_output.hpp.
#include "study/studies/study_output.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <filesystem>
#include <stdexcept>

#include "core/name_list.hpp"
#include "io/checkpoint.hpp"
#include "io/output_target.hpp"
#include "io/terrain_json.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/calibration.hpp"

namespace rover::study {

std::string results_path_label(const std::string& path, bool is_default) {
  return (is_default ? "the default output '" : "--out '") + path + "'";
}

std::string checked_results_path(const std::string& name, const std::string& requested, bool csv_allowed,
                                 bool requested_is_default) {
  const std::string path = requested.empty() ? "results/" + name + ".h5" : requested;
  const std::string out = results_path_label(path, requested.empty() || requested_is_default);
  const std::filesystem::path p(path);
  if (const auto file = p.filename(); std::filesystem::is_directory(p) || file.empty() || file == "." || file == "..")
    throw std::invalid_argument(out + " is a directory; give a file name ending in .h5");
  if (const std::string refusal = io::extension_only_refusal(path); !refusal.empty())
    throw std::invalid_argument(out + " " + refusal);
  if (csv_allowed && p.extension() != ".h5" && p.extension() != ".csv")
    throw std::invalid_argument(out + " must end in .csv or .h5");
  if (!csv_allowed && p.extension() != ".h5")
    throw std::invalid_argument(out + " must end in .h5 (an HDF5 file)");
  if (const std::string refusal = io::parent_directory_refusal(path); !refusal.empty())
    throw std::invalid_argument(out + ": " + refusal);
  // Can a file be created there? (Found now, not after the study ran.) A
  // directory still to be made is made, and probed, only when the run begins.
  std::error_code error;
  if (const auto dir = p.parent_path(); !dir.empty() && !std::filesystem::is_directory(dir, error)) return path;
  // One name per process: every rank checks the path at once.
  const std::string probe = path + ".probe-" + std::to_string(::getpid());
  try {
    io::create_temporary(probe, path);  // never written through a link
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(std::string("cannot write '") + path + "': " + e.what());
  }
  std::filesystem::remove(probe);
  return path;
}

void require_memory(const std::string& what, double bytes, const io::MemoryLimit& limit) {
  if (bytes <= limit.bytes) return;
  char text[160];
  std::snprintf(text, sizeof text, "would hold %.3g GB of %s in memory, more than the %.3g GB of ", bytes / 1e9,
                what.c_str(), limit.bytes / 1e9);
  throw std::invalid_argument(text + limit.what + ": reduce the study's size (--samples)");
}

std::vector<PlannedFigure> summary_figure(PlotSelection plots) {
  if (plots == PlotSelection::kNone) return {};
  return {{"_summary.png", "the summary"}};
}

std::string shared_figure_names(const std::string& results_path, const std::vector<PlannedFigure>& figures) {
  std::string problems;
  for (std::size_t i = 0; i < figures.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      if (figures[i].suffix != figures[j].suffix) continue;
      problems += (problems.empty() ? "" : "; ") + std::string("the figures of ") + figures[j].shows + " and of " +
                  figures[i].shows + " would both be written to " + sibling_path(results_path, figures[i].suffix);
      break;
    }
  return problems;
}

std::string sibling_path(const std::string& results_path, const std::string& suffix) {
  std::filesystem::path p(results_path);
  const std::string stem = p.stem().string();
  return (p.parent_path() / (stem + suffix)).string();
}

void write_integrator_provenance(io::Hdf5Writer& h5, const IntegratorSettings& integrator) {
  h5.attribute("/", "integrator", integrator_name(integrator.method));
  if (integrator.method == IntegratorMethod::kRungeKutta4) {
    // A step not known (runs read from a file that does not record it) is not recorded either.
    if (std::isfinite(integrator.fixed_step_s)) h5.attribute("/", "fixed_step_s", integrator.fixed_step_s);
    return;
  }
  h5.attribute("/", "rtol", integrator.relative_tolerance);
  h5.attribute("/", "atol", integrator.absolute_tolerance);
  h5.attribute("/", "slip_tol", integrator.slip_tolerance);
}

std::optional<IntegratorSettings> recorded_integrator(const io::Hdf5Reader& h5) {
  if (!h5.has_attribute("/", "integrator")) return std::nullopt;
  IntegratorSettings s;
  try {
    s = default_integrator_settings(integrator_from_name(h5.attribute_string("/", "integrator")));
  } catch (const std::invalid_argument&) {  // a method of no version of rover: nothing to compare
    return std::nullopt;
  }
  if (s.method == IntegratorMethod::kRungeKutta4) {
    s.fixed_step_s = h5.has_attribute("/", "fixed_step_s") ? h5.attribute_double("/", "fixed_step_s") : std::nan("");
    return s;
  }
  if (!h5.has_attribute("/", "rtol") || !h5.has_attribute("/", "atol")) return std::nullopt;
  s.relative_tolerance = h5.attribute_double("/", "rtol");
  s.absolute_tolerance = h5.attribute_double("/", "atol");
  if (h5.has_attribute("/", "slip_tol")) s.slip_tolerance = h5.attribute_double("/", "slip_tol");
  return s;
}

void write_base_provenance(io::Hdf5Writer& h5, const std::string& type, const std::string& name,
                           const std::string& study_path, const IntegratorSettings* integrator,
                           const std::string& fingerprint) {
  h5.attribute("/", "study", type);
  h5.attribute("/", "name", name);
  h5.attribute("/", "study_file", study_path);
  h5.attribute("/", "study_json", file_text(study_path));
  if (integrator != nullptr) write_integrator_provenance(h5, *integrator);
  h5.attribute("/", "ranks", static_cast<long long>(world_size()));
  h5.attribute("/", "fingerprint", io::key_summary(fingerprint));
  h5.attribute("/", "project_version", ROVER_VERSION);
}

void write_study_provenance(io::Hdf5Writer& h5, const StudySpec& spec, const std::string& fingerprint,
                            const IntegratorSettings* runs_integrator) {
  const IntegratorSettings* integrator =
      runs_integrator != nullptr ? runs_integrator : spec.rover ? &spec.rover->nominal().scenario.integrator : nullptr;
  write_base_provenance(h5, spec.type, spec.name, spec.path, integrator, fingerprint);
  h5.attribute("/", "description", spec.description);
  if (spec.rover) {
    const auto& setup = spec.rover->nominal();
    h5.attribute("/", "scenario", setup.scenario.name);
    h5.attribute("/", "scenario_file", setup.scenario_path);
    h5.attribute("/", "rover_file", setup.rover_path);
    h5.attribute("/", "terrain_file", setup.terrain_path);
    h5.attribute("/", "scenario_json", spec.rover->sources().scenario.dump());
    h5.attribute("/", "rover_json", spec.rover->sources().rover.dump());
    h5.attribute("/", io::kTerrainDigestAttribute, io::terrain_digest(spec.rover->sources().terrain));
  } else {
    h5.attribute("/", "model", spec.model->describe());
  }
  h5.attribute("/", "design", design_type_name(spec.design.type));
  h5.unsigned_attribute("/", "seed", spec.design.seed);
  h5.attribute("/", "samples", static_cast<long long>(spec.design.samples));
  std::string warnings;  // one per line
  for (const std::string& w : spec.warnings) warnings += (warnings.empty() ? "" : "\n") + w;
  if (!warnings.empty()) h5.attribute("/", "input_warnings", warnings);
}

void write_qoi_definitions(io::Hdf5Writer& h5, const std::vector<QoiSpec>& qois, const std::string& prefix) {
  for (const QoiSpec& q : qois) h5.attribute(prefix + "/qoi/" + q.name, kQoiDefinitionAttribute, qoi_definition(q));
}

void write_undefined_indices(io::Hdf5Writer& h5, const std::vector<std::string>& qois) {
  if (!qois.empty()) h5.attribute("/", "undefined_indices", comma_separated(qois));
}

void write_study_inputs(io::Hdf5Writer& h5, const StudySpec& spec, const DesignMatrix& x) {
  std::vector<std::string> names, labels, distributions;
  for (const UncertainInput& in : spec.inputs) {
    names.push_back(in.name);
    labels.push_back(in.label);
    distributions.push_back(in.distribution.describe());
  }
  if (names.empty()) return;
  h5.write("/inputs/names", names);
  h5.write("/inputs/labels", labels);
  h5.write("/inputs/distributions", distributions);
  h5.write("/inputs/values", Eigen::MatrixXd(x));
}

std::string runs_description(const StudySpec& spec) {
  if (!spec.rover) return spec.model->describe();
  return spec.rover->describe() + " on " + describe_integrator(spec.rover->nominal().scenario.integrator) +
         (spec.accuracy_choice.empty() ? "" : ", which \"accuracy\" chose");
}

}  // namespace rover::study
