// See surrogate_training.hpp.
#include "study/studies/surrogate_training.hpp"
#include "core/number_text.hpp"
#include "core/name_list.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "io/hdf5_file.hpp"
#include "io/json_reader.hpp"
#include "io/terrain_json.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/studies/calibration.hpp"
#include "study/studies/study_output.hpp"

namespace rover::study {
namespace {

// Messages about one file: "<path>: <role> runs: <what>".
struct FileErrors {
  std::string path, role;
  [[noreturn]] void fail(const std::string& what) const {
    throw io::ConfigError(path + ": " + role + " runs: " + what);
  }
};

// The file's column of each study input; refuses a missing input.
std::vector<Eigen::Index> input_columns(const FileErrors& errors, const std::vector<std::string>& names,
                                        const SurrogateStudy& study) {
  std::vector<Eigen::Index> columns;
  for (const UncertainInput& in : study.spec.inputs) {
    const auto it = std::find(names.begin(), names.end(), in.name);
    if (it == names.end())
      errors.fail("no input '" + in.label + "' (" + in.name + ") in /inputs/names (" + comma_separated(names) + ")");
    columns.push_back(it - names.begin());
  }
  return columns;
}

// "'M0_11' (s_structure.preload_mean[0])": the column as the runs' file labels
// it (/inputs/labels, the name typed in their study or design) and its name.
std::string column_text(const std::vector<std::string>& names, const std::vector<std::string>& labels,
                        std::size_t k) {
  if (k >= labels.size() || labels[k].empty() || labels[k] == names[k]) return "'" + names[k] + "'";
  return "'" + labels[k] + "' (" + names[k] + ")";
}

// An input the study does not list, held at `value` in every run of the file,
// is the study's own nominal value of it (within kHeldInputRelativeTolerance):
// else the runs were made on another rover or scenario than the study's.
void check_held_input(const FileErrors& errors, const std::string& column, const std::string& name, double value,
                      const SurrogateStudy& study) {
  if (!study.spec.rover) return;  // an analytic model: no nominal values
  const ParameterSpace& space = study.spec.rover->parameter_space();
  const std::string held = "input " + column + " is " + number_text(value) + " in every run, ";
  const std::string scenario = study.spec.rover->sources().scenario_path;
  if (!space.contains(name))
    errors.fail(held + "but names no parameter of the rover or the scenario: the runs cannot be checked against "
                "those of " + study.spec.path + "; train on runs that vary only its \"parameters\"");
  const double nominal = space.nominal(space.canonical(name));
  const double scale = std::max(std::abs(value), std::abs(nominal));
  if (std::abs(value - nominal) <= kHeldInputRelativeTolerance * scale) return;
  const std::string study_value = std::isnan(nominal)
                                      ? "the study's scenario " + scenario + " does not set it"
                                      : "the study's scenario " + scenario + " and its rover have " + number_text(nominal);
  errors.fail(held + "but " + study_value + ", and " + study.spec.path +
              " does not vary it: the runs were made on another rover or scenario; list it under \"parameters\", "
              "or train on runs made on the study's");
}

// The inputs of the file that the study does not list: none may vary over
// the runs, and each must hold the study's nominal value.
void check_unlisted_inputs(const FileErrors& errors, const std::vector<std::string>& names,
                           const std::vector<std::string>& labels, const Eigen::MatrixXd& values,
                           const std::vector<Eigen::Index>& columns, const SurrogateStudy& study) {
  for (std::size_t k = 0; k < names.size(); ++k) {
    const auto column = values.col(static_cast<Eigen::Index>(k));
    if (std::find(columns.begin(), columns.end(), static_cast<Eigen::Index>(k)) != columns.end() ||
        values.rows() == 0)
      continue;
    if (column.minCoeff() != column.maxCoeff())
      errors.fail("input '" + names[k] + "' varies over the runs (" + number_text(column.minCoeff()) + " to " +
                  number_text(column.maxCoeff()) + ") but is not a parameter of " + study.spec.path +
                  ": list it under \"parameters\"");
    check_held_input(errors, column_text(names, labels, k), names[k], column(0), study);
  }
}

std::vector<int> statuses(const FileErrors& errors, const io::Hdf5Reader& h5, const Eigen::MatrixXd& y) {
  if (!h5.exists("/samples/status")) {
    std::vector<int> status;
    for (Eigen::Index i = 0; i < y.rows(); ++i)
      status.push_back(y.row(i).allFinite() ? run_status::kOk : run_status::kError);
    return status;
  }
  std::vector<int> status = h5.read_ints("/samples/status");
  if (static_cast<Eigen::Index>(status.size()) != y.rows())
    errors.fail("/samples/status has " + std::to_string(status.size()) + " entries for " +
                std::to_string(y.rows()) + " runs");
  return status;
}

// Every successful run's inputs lie in the support of their distributions.
void check_support(const FileErrors& errors, const TrainingRuns& runs, const SurrogateStudy& study) {
  for (Eigen::Index i = 0; i < runs.x.rows(); ++i) {
    if (runs.status[static_cast<std::size_t>(i)] != run_status::kOk) continue;
    for (std::size_t j = 0; j < study.spec.inputs.size(); ++j) {
      const UncertainInput& in = study.spec.inputs[j];
      const double v = runs.x(i, static_cast<Eigen::Index>(j));
      if (v >= in.distribution.support_lower() && v <= in.distribution.support_upper()) continue;
      errors.fail("run " + std::to_string(i) + ": " + in.label + " = " + number_text(v) + " lies outside its distribution " +
                  in.distribution.describe() + " in " + study.spec.path);
    }
  }
}

// Where two configs differ, ignoring what only names or places them: "field
// 'duration' (0.1 against 0.3)", or empty when they are the same.
std::string first_difference(const io::Json& file, const io::Json& study) {
  io::Json a = file, b = study;
  for (const char* key : {"name", "description", "rover", "terrain"}) {
    if (a.is_object()) a.erase(key);
    if (b.is_object()) b.erase(key);
  }
  const io::Json patch = io::Json::diff(b, a);
  if (patch.empty()) return "";
  const std::string where = patch[0].value("path", std::string("/"));
  const io::Json::json_pointer pointer(where);
  auto value = [&](const io::Json& j) { return j.contains(pointer) ? j.at(pointer).dump() : std::string("absent"); };
  return "field '" + (where.size() > 1 ? where.substr(1) : where) + "' (" + value(a) + " against " + value(b) + ")";
}

// The file's QoIs of the study's names are the study's QoIs: the same
// settling band, or the same reference curve and time offset of rms_vs, as
// the definitions the file records with its values say (a file without
// them, from an analytic model, is not checked).
void check_qoi_definitions(const FileErrors& errors, const io::Hdf5Reader& h5, const SurrogateStudy& study) {
  if (!study.spec.rover) return;
  for (const QoiSpec& q : study.spec.rover->qois()) {
    const std::string values = "/qoi/" + q.name;
    if (!h5.exists(values) || !h5.has_attribute(values, kQoiDefinitionAttribute)) continue;
    const std::string recorded = h5.attribute_string(values, kQoiDefinitionAttribute), own = qoi_definition(q);
    if (recorded != own)
      errors.fail("QoI '" + q.name + "': its runs computed " + recorded + ", but " + study.spec.path +
                  " defines it as " + own + ": train on runs of the same QoI (the same band, reference "
                  "curve and time offset), or give the study's QoI that definition");
  }
}

// The runs of a file were made on the study's ground: the terrain digest the
// file records (/ terrain_digest) equals the digest of the study's terrain,
// whatever files named it. False when the file records none.
bool check_terrain(const FileErrors& errors, const io::Hdf5Reader& h5, const io::ScenarioSources& sources) {
  if (!h5.has_attribute("/", io::kTerrainDigestAttribute)) return false;
  const std::string recorded = h5.attribute_string("/", io::kTerrainDigestAttribute);
  const std::string own = io::terrain_digest(sources.terrain);
  if (recorded != own)
    errors.fail("were made on another terrain than the study's (" +
                (sources.terrain_path.empty() ? "flat ground, as " + sources.scenario_path + " names no terrain"
                                              : sources.terrain_path) +
                "): the ground's digest is " + recorded + " against " + own +
                "; the terrain file was changed since the runs, or they were made on another: train on runs made "
                "on this terrain");
  return true;
}

// The runs of a file were made on the study's scenario, rover and terrain:
// the scenario and rover configs the file records (/ scenario_json,
// rover_json) equal the study's, up to names, descriptions and file paths,
// and so does the ground (check_terrain).
void check_scenario(const FileErrors& errors, const io::Hdf5Reader& h5, const SurrogateStudy& study,
                    TrainingRuns& runs) {
  if (!study.spec.rover) return;  // an analytic model: no scenario
  const io::ScenarioSources& sources = study.spec.rover->sources();
  const std::pair<const char*, const io::Json*> configs[] = {{"scenario", &sources.scenario},
                                                             {"rover", &sources.rover}};
  std::vector<std::string> unrecorded, attributes;
  for (const auto& [what, config] : configs) {
    const std::string attribute = std::string(what) + "_json";
    if (!h5.has_attribute("/", attribute)) {  // a file of an analytic model, or of an earlier version
      unrecorded.push_back(std::string(what) + " config");
      attributes.push_back("/" + attribute);
      continue;
    }
    const io::Json recorded = io::parse_json_quietly(h5.attribute_string("/", attribute));
    if (const std::string difference = first_difference(recorded, *config); !difference.empty())
      errors.fail(std::string("were made on another ") + what + " than the study's " +
                  (what == std::string("scenario") ? sources.scenario_path : sources.rover_path) + ": " + difference +
                  "; name the " + what + " file the runs were made on");
  }
  if (!check_terrain(errors, h5, sources)) {
    unrecorded.push_back("terrain digest");
    attributes.push_back(std::string("/") + io::kTerrainDigestAttribute);
  }
  if (unrecorded.empty()) return;
  const std::string which = comma_separated(unrecorded);
  runs.unchecked_provenance = errors.path + " records no " + which + " (" + comma_separated(attributes) +
                              "; a file of an earlier version or of an analytic model): its runs cannot be checked "
                              "against the study's scenario, rover and terrain; make sure they were made on them";
}

// The settings that make two integrators' runs the same: the fixed step of
// rk4 (a step not recorded, NaN, matches none), the tolerances of the others.
bool same_integrator(const IntegratorSettings& a, const IntegratorSettings& b) {
  if (a.method != b.method) return false;
  if (a.method == IntegratorMethod::kRungeKutta4) return a.fixed_step_s == b.fixed_step_s;
  return a.relative_tolerance == b.relative_tolerance && a.absolute_tolerance == b.absolute_tolerance &&
         a.slip_tolerance == b.slip_tolerance;
}

// describe_integrator(), or for rk4 runs whose file records no step, that it is not known.
std::string describe_runs_integrator(const IntegratorSettings& i) {
  if (i.method == IntegratorMethod::kRungeKutta4 && !std::isfinite(i.fixed_step_s))
    return std::string(integrator_name(i.method)) + " with a fixed step its file does not record (a file of an "
                                                    "earlier version)";
  return describe_integrator(i);
}

// Per input, the distance within which two runs are one (kSameRunRelativeDistance).
Eigen::RowVectorXd same_run_distances(const DesignMatrix& x) {
  if (x.rows() == 0) return Eigen::RowVectorXd::Zero(x.cols());
  const Eigen::RowVectorXd span = x.colwise().maxCoeff() - x.colwise().minCoeff();
  const Eigen::RowVectorXd magnitude = x.cwiseAbs().colwise().maxCoeff();
  return kSameRunRelativeDistance * (span.array() > 0.0).select(span, magnitude);
}

bool same_run(const auto& a, const auto& b, const Eigen::RowVectorXd& distance) {
  return ((a - b).cwiseAbs().array() <= distance.array()).all();
}

}  // namespace

std::string integrator_mismatch(const SurrogateStudy& study, const TrainingRuns& training,
                                const TrainingRuns& held_out) {
  if (!study.spec.rover) return "";
  const IntegratorSettings& own = study.spec.rover->nominal().scenario.integrator;
  const IntegratorSettings& trained_with = training.integrator.value_or(own);
  std::string text;
  if (!same_integrator(trained_with, own))
    text = "the training runs were made with " + describe_runs_integrator(trained_with) + ", not the study's " +
           describe_integrator(own) + ": the surrogate stands for the training runs' integrator, and the result records it";
  if (held_out.integrator && !same_integrator(*held_out.integrator, trained_with))
    text += std::string(text.empty() ? "" : "; ") + "the held-out runs were made with " +
            describe_runs_integrator(*held_out.integrator) + ", the training runs with " +
            describe_runs_integrator(trained_with) +
            ": the held-out Q2 includes the difference of the two integrators";
  return text;
}

std::string shared_runs(const TrainingRuns& training, const TrainingRuns& held_out) {
  const Eigen::RowVectorXd distance = same_run_distances(training.x);
  long long shared = 0;
  std::string first;
  for (Eigen::Index i = 0; i < held_out.x.rows(); ++i)
    for (Eigen::Index j = 0; j < training.x.rows(); ++j) {
      if (!same_run(held_out.x.row(i), training.x.row(j), distance)) continue;
      if (shared++ == 0) first = "held-out run " + std::to_string(i) + " is training run " + std::to_string(j);
      break;
    }
  if (shared == 0) return "";
  return std::to_string(shared) + " of the " + std::to_string(held_out.runs()) + " held-out runs (" + held_out.source +
         ") are training runs too (" + first + "): a held-out Q2 needs runs the surrogate was not fitted to";
}

long long repeated_runs(const TrainingRuns& runs) {
  std::vector<Eigen::Index> order(static_cast<std::size_t>(runs.runs()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
    const auto ra = runs.x.row(a), rb = runs.x.row(b);
    return std::lexicographical_compare(ra.begin(), ra.end(), rb.begin(), rb.end());
  });
  const Eigen::RowVectorXd distance = same_run_distances(runs.x);
  long long repeats = 0;
  for (std::size_t k = 1; k < order.size(); ++k)
    repeats += same_run(runs.x.row(order[k]), runs.x.row(order[k - 1]), distance) ? 1 : 0;
  return repeats;
}

int TrainingRuns::failed_runs() const {
  return static_cast<int>(std::count_if(status.begin(), status.end(), [](int s) { return s != run_status::kOk; }));
}

TrainingRuns TrainingRuns::slice(int first, int count) const {
  TrainingRuns out;
  out.source = source;
  out.x = x.middleRows(first, count);
  out.y = y.middleRows(first, count);
  out.status.assign(status.begin() + first, status.begin() + first + count);
  out.messages.assign(messages.begin() + first, messages.begin() + first + count);
  out.unchecked_provenance = unchecked_provenance;
  out.integrator = integrator;
  for (const Eigen::MatrixXd& c : curves) out.curves.push_back(c.middleRows(first, count));
  return out;
}

TrainingRuns read_result_runs(const std::string& path, const SurrogateStudy& study, const std::string& role) {
  const FileErrors errors{path, role};
  const io::Hdf5Reader h5(path);
  if (!h5.exists("/inputs/names") || !h5.exists("/inputs/values"))
    errors.fail("no /inputs/names and /inputs/values: not a result of montecarlo, evaluate, sensitivity or surrogate");
  const std::vector<std::string> names = h5.read_strings("/inputs/names");
  const Eigen::MatrixXd values = h5.read_matrix("/inputs/values");
  if (values.cols() != static_cast<Eigen::Index>(names.size()))
    errors.fail("/inputs/values has " + std::to_string(values.cols()) + " columns for " +
                std::to_string(names.size()) + " names");
  const std::vector<Eigen::Index> columns = input_columns(errors, names, study);
  const std::vector<std::string> labels =
      h5.exists("/inputs/labels") ? h5.read_strings("/inputs/labels") : std::vector<std::string>{};
  check_unlisted_inputs(errors, names, labels, values, columns, study);
  TrainingRuns runs;
  runs.source = path;
  runs.x.resize(values.rows(), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t j = 0; j < columns.size(); ++j) runs.x.col(static_cast<Eigen::Index>(j)) = values.col(columns[j]);
  const std::vector<std::string> qois = study.qoi_names();
  runs.y.resize(values.rows(), static_cast<Eigen::Index>(qois.size()));
  for (std::size_t q = 0; q < qois.size(); ++q) {
    if (!h5.exists("/qoi/" + qois[q]))
      errors.fail("no QoI '" + qois[q] + "' (/qoi holds: " + (h5.exists("/qoi") ? comma_separated(h5.list("/qoi")) : "nothing") + ")");
    const std::vector<double> v = h5.read_doubles("/qoi/" + qois[q]);
    if (static_cast<Eigen::Index>(v.size()) != values.rows())
      errors.fail("/qoi/" + qois[q] + " has " + std::to_string(v.size()) + " values for " +
                  std::to_string(values.rows()) + " runs");
    runs.y.col(static_cast<Eigen::Index>(q)) = Eigen::Map<const Eigen::VectorXd>(v.data(), values.rows());
  }
  check_qoi_definitions(errors, h5, study);
  runs.status = statuses(errors, h5, runs.y);
  runs.messages = h5.exists("/samples/message") ? h5.read_strings("/samples/message")
                                                 : std::vector<std::string>(runs.status.size());
  runs.messages.resize(runs.status.size());
  for (Eigen::Index i = 0; i < runs.x.rows(); ++i)
    if (runs.status[static_cast<std::size_t>(i)] != run_status::kOk) runs.y.row(i).setConstant(std::nan(""));
  check_support(errors, runs, study);
  check_scenario(errors, h5, study, runs);
  runs.integrator = recorded_integrator(h5);
  return runs;
}

std::string check_result_provenance(const std::string& path, const SurrogateStudy& study, const std::string& role) {
  TrainingRuns runs;
  check_scenario(FileErrors{path, role}, io::Hdf5Reader(path), study, runs);
  return runs.unchecked_provenance;
}

TrainingRuns run_design_runs(const SurrogateStudy& study, const StudyRunOptions& options) {
  const StudySpec& spec = study.spec;
  const StudyModel& model = *spec.model;
  const RecordLayout layout = model.layout();
  TrainingRuns runs;
  runs.source = "design";
  runs.x = study_design(spec);
  runs.y.resize(runs.x.rows(), layout.qoi_count);
  runs.curves.assign(static_cast<std::size_t>(layout.channel_count),
                     Eigen::MatrixXd::Constant(runs.x.rows(), layout.time_samples, std::nan("")));
  auto compute = [&](int i) { return encode_record(i, model.run(runs.x.row(i).data())); };
  auto consume = [&](TaskResult&& task) {
    const Eigen::Index i = task.index;
    const RunRecord record = decode_record(layout, std::move(task));
    for (int q = 0; q < layout.qoi_count; ++q)
      runs.y(i, q) = record.ok() ? record.qoi[static_cast<std::size_t>(q)] : std::nan("");
    for (int c = 0; c < layout.channel_count && record.ok(); ++c) {
      const double* curve = record.curve(c, layout.time_samples);
      for (int s = 0; s < layout.time_samples; ++s) runs.curves[static_cast<std::size_t>(c)](i, s) = curve[s];
    }
    runs.status.push_back(record.status);
    runs.messages.push_back(record.message);
  };
  stream_study_tasks(static_cast<int>(runs.x.rows()), compute, consume, options);
  if (world_rank() != 0) return TrainingRuns{};
  return runs;
}

}  // namespace rover::study
