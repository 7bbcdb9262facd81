// See evaluate.hpp.
#include "study/studies/evaluate.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>

#include "io/checkpoint.hpp"
#include "io/csv.hpp"
#include "io/decimal_number.hpp"
#include "core/number_text.hpp"
#include "io/hdf5_file.hpp"
#include "io/json_reader.hpp"
#include "io/text_encoding.hpp"
#include "io/output_target.hpp"
#include "io/terrain_json.hpp"
#include "study/runtime/rank0_broadcast.hpp"
#include "study/studies/calibration.hpp"
#include "study/studies/study_output.hpp"
#include "study/studies/summary_figure.hpp"
#include "study/runtime/study_runner.hpp"
#include "study/model/qoi.hpp"
#include "study/studies/study_spec.hpp"

namespace rover::study {
namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

std::vector<std::string> split_commas(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

std::string csv_quoted(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c == '\n' ? ' ' : c;
  }
  return out + "\"";
}

}  // namespace

DesignTable read_design_csv(const std::string& path, const std::function<void(const DesignTable&)>& check_columns) {
  if (const std::string problem = io::input_path_problem(path, "a design file (CSV)"); !problem.empty())
    throw io::ConfigError(path + ": " + problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io::ConfigError(path + ": cannot read the design file");
  DesignTable table;
  table.path = path;
  std::string line;
  std::vector<std::vector<double>> rows;
  int line_number = 0;
  bool header = true;
  while (std::getline(in, line)) {
    ++line_number;
    for (const std::string& problem : {io::text_encoding_problem(line), io::line_ending_problem(line)})
      if (!problem.empty()) throw io::ConfigError(path + ":" + std::to_string(line_number) + ": " + problem);
    if (line_number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    if (trim(line).empty()) continue;
    const std::vector<std::string> cells = split_commas(line);
    const std::string where = path + ":" + std::to_string(line_number);
    if (header) {
      table.columns = cells;
      for (const std::string& name : table.columns)
        if (const std::string problem = io::csv_separator_problem(name); !problem.empty() && !name.starts_with('"'))
          throw io::ConfigError(where + ": " + problem);
      for (std::string& name : table.columns) name = io::unquoted_csv_cell(name);
      table.header_line = line_number;
      for (std::size_t j = 0; j < cells.size(); ++j)
        if (cells[j].empty()) throw io::ConfigError(where + ": column " + std::to_string(j + 1) + " has no name");
      if (check_columns) check_columns(table);  // a column to remove is named before any of its cells
      header = false;
      continue;
    }
    if (cells.size() != table.columns.size())
      throw io::ConfigError(where + ": expected " + std::to_string(table.columns.size()) + " values, got " +
                            std::to_string(cells.size()));
    std::vector<double> row;
    for (std::size_t j = 0; j < cells.size(); ++j) {
      // A value quoted as spreadsheets write every cell ("0.25") reads as the number.
      const std::string text = trim(io::unquoted_csv_cell(cells[j]));
      const io::DecimalNumber cell = io::parse_decimal_number(text);
      const std::string hint = io::decimal_number_hint(cells[j]);
      if (cell.status != io::DecimalStatus::kOk)
        throw io::ConfigError(where + ": column " + std::to_string(j + 1) + " (" + table.columns[j] +
                              "): '" + cells[j] + "' is not a finite number" + (hint.empty() ? "" : ": " + hint));
      row.push_back(cell.value);
    }
    rows.push_back(std::move(row));
    table.line_numbers.push_back(line_number);
  }
  if (header) throw io::ConfigError(path + ": empty file (expected a header of parameter names)");
  if (rows.empty()) throw io::ConfigError(path + ": no rows after the header");
  table.values.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(table.columns.size()));
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < rows[i].size(); ++j)
      table.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = rows[i][j];
  return table;
}

namespace {

// A column rover evaluate writes after the inputs: a QoI, "status" or "message".
bool is_evaluate_output_column(const std::string& column) {
  const std::vector<std::string>& qois = qoi_kind_names();
  return column == "status" || column == "message" || std::find(qois.begin(), qois.end(), column) != qois.end();
}

std::vector<std::string> canonical_columns(const DesignTable& design, const ParameterSpace& space) {
  std::vector<std::string> names;
  for (std::size_t j = 0; j < design.columns.size(); ++j) {
    if (is_evaluate_output_column(design.columns[j]))
      throw io::ConfigError(design.path + ":" + std::to_string(design.header_line) + ": column " +
                            std::to_string(j + 1) + " '" + design.columns[j] +
                            "' is an output of rover evaluate, not a parameter: a design holds input columns "
                            "only; remove the output columns (a result's own inputs are its first columns)");
    try {
      names.push_back(space.canonical(design.columns[j]));
    } catch (const std::invalid_argument& e) {
      throw io::ConfigError(design.path + ":" + std::to_string(design.header_line) +
                            ": column " + std::to_string(j + 1) + ": " + e.what());
    }
    for (std::size_t k = 0; k < j; ++k) {
      if (!parameters_overlap(names[k], names[j])) continue;
      const std::string& first = design.columns[k];
      const std::string& second = design.columns[j];
      const std::string columns = "columns " + std::to_string(k + 1) + " and " + std::to_string(j + 1);
      const std::string where = design.path + ":" + std::to_string(design.header_line) + ": ";
      if (names[k] != names[j])
        throw io::ConfigError(where + columns + ", '" + first + "' and '" + second + "', overlap: " +
                              overlap_reason(names[k], names[j]));
      throw io::ConfigError(where +
                            (first == second ? "column '" + first + "' is given twice (" + columns + ")"
                                             : columns + ", '" + first + "' and '" + second +
                                                   "', name the same parameter (" + names[j] + ")") +
                            "; keep one");
    }
  }
  return names;
}

std::vector<QoiSpec> plain_qois(const std::vector<std::string>& qoi_names) {
  std::vector<QoiSpec> qois;
  for (const std::string& q : qoi_names) {
    QoiSpec spec;
    spec.name = q;
    spec.kind = qoi_kind_from_name(q);
    if (spec.kind == QoiKind::kRmsVs)
      throw std::invalid_argument("--qoi rms_vs needs a reference curve: use a montecarlo study file for it");
    qois.push_back(spec);
  }
  return qois;
}

// "c_q = 0.2, geometry.wheel_radius = 0.3": row `i` as the file gives it
// (its first kShownColumns columns), for a message about what it causes.
std::string row_values_text(const DesignTable& design, Eigen::Index i) {
  constexpr std::size_t kShownColumns = 8;
  std::string text;
  for (std::size_t j = 0; j < design.columns.size() && j < kShownColumns; ++j)
    text += (j == 0 ? "" : ", ") + design.columns[j] + " = " +
            exact_number_text(design.values(i, static_cast<Eigen::Index>(j)));
  if (design.columns.size() > kShownColumns) text += ", ...";
  return text;
}

// Every row is checked before any run starts. The model's message may name
// the scenario field the row's values upset (a larger wheel radius puts the
// wheels below the ground at the scenario's initial_q): the row is named too.
void check_rows(const DesignTable& design, const RoverStudyModel& model) {
  for (Eigen::Index i = 0; i < design.values.rows(); ++i) {
    try {
      (void)model.setup_at(design.values.row(i).data());
    } catch (const std::exception& e) {
      throw io::ConfigError(design.path + ":" + std::to_string(design.line_numbers[static_cast<std::size_t>(i)]) +
                            ": this row's values (" + row_values_text(design, i) +
                            ") are not a valid configuration: " + e.what());
    }
  }
}

// The digest of the files, and the flags that change the rows' results as settings.
std::string evaluate_fingerprint(const EvaluateRequest& request, const io::ScenarioSources& sources) {
  std::string qoi, channels;
  for (const auto& q : request.qoi_names) qoi += (qoi.empty() ? "" : ",") + q;
  for (const auto& c : request.channel_names) channels += (channels.empty() ? "" : ",") + c;
  std::string key = io::config_fingerprint(file_text(request.design_path) + file_text(request.scenario_path) +
                                           file_text(sources.rover_path) + file_text(sources.terrain_path));
  key = with_setting(key, "--qoi", qoi, true);
  key = with_setting(key, "--channels", channels, true);
  const bool integrator = !request.integrator.empty();
  return with_setting(key, "--integrator", integrator ? request.integrator : "integrator", integrator,
                      "the scenario");
}

// --integrator's method at its default settings, which the scenario (with
// them in place, as `scenario` has) must be able to run with.
void refuse_flag_integrator_the_scenario_refuses(const EvaluateRequest& request, const Scenario& scenario) {
  if (std::string why; !scenario_is_valid(scenario, &why))
    throw std::invalid_argument("--integrator " + request.integrator + " at its default settings: " + why + " (" +
                                request.scenario_path + ": duration " + number_text(scenario.duration_s) +
                                " s, output rate " + number_text(scenario.output_rate_hz) +
                                " Hz); give the scenario an \"integrator\" block instead");
}

}  // namespace

EvaluateStudy load_evaluate(const EvaluateRequest& request) {
  if (request.out_path.ends_with(".csv") && !request.channel_names.empty())
    throw std::invalid_argument("--channels needs an .h5 output (curves do not fit a CSV row)");
  EvaluateStudy s;
  s.request = request;
  io::ScenarioSources sources = io::read_scenario_sources(request.scenario_path);
  const ParameterSpace space(sources.rover, sources.scenario);
  s.design = read_design_csv(request.design_path, [&](const DesignTable& t) { s.names = canonical_columns(t, space); });
  std::vector<Channel> channels;
  for (const std::string& c : request.channel_names) channels.push_back(channel_from_name(c));
  std::optional<IntegratorSettings> integrator;
  if (!request.integrator.empty())
    integrator = default_integrator_settings(integrator_from_name(request.integrator));
  s.fingerprint = evaluate_fingerprint(request, sources);
  s.files.add(request.design_path, "--design");
  s.files.add(request.scenario_path, "--scenario");
  s.files.add_all(sources.files);
  s.model = std::make_shared<RoverStudyModel>(std::move(sources), s.names, plain_qois(request.qoi_names), channels,
                                              integrator);
  if (integrator) refuse_flag_integrator_the_scenario_refuses(request, s.model->nominal().scenario);
  // Rank 0 checks and every rank learns the verdict: a refusal on rank 0
  // alone would leave the others waiting for it in the run.
  std::string refusal;
  if (world_rank() == 0) {
    try {
      check_rows(s.design, *s.model);
    } catch (const io::ConfigError& e) {
      refusal = e.what();
    }
  }
  if (broadcast_flag_from_rank0(!refusal.empty())) throw io::ConfigError(refusal.empty() ? "a design row is refused (rank 0 says which)" : refusal);
  return s;
}

// A done row whose settling time is not one (settled_before_end) says so in
// its message; its status stays done.
void note_unsettled_rows(const RoverStudyModel& model, EvaluateResult& result) {
  const double duration_s = model.nominal().scenario.duration_s;
  for (std::size_t q = 0; q < result.qoi.size(); ++q) {
    const QoiSpec& qoi = model.qois()[q];
    if (qoi.kind != QoiKind::kSettlingTime) continue;
    for (std::size_t i = 0; i < result.qoi[q].size(); ++i) {
      if (result.status[i] != run_status::kOk || settled_before_end(result.qoi[q][i], duration_s)) continue;
      std::string& message = result.messages[i];
      message += (message.empty() ? "" : "; ") + qoi.name + " is no settling time: B_l z stayed within its " +
                 number_text(qoi.settling_band) + " m band for less than the last " +
                 number_text(100.0 * kMinSettledShare) + " % of the run";
    }
  }
}

EvaluateResult run_evaluate(const EvaluateStudy& study, const StudyRuntime& runtime) {
  const RoverStudyModel& model = *study.model;
  const DesignMatrix& x = study.design.values;
  const std::vector<std::string>& channels = study.request.channel_names;
  const auto rows = static_cast<int>(x.rows());
  const RecordLayout layout = model.layout();
  const auto T = static_cast<std::size_t>(layout.time_samples);
  io::Hdf5Writer* h5 = runtime.h5;
  if (h5 != nullptr)
    for (const std::string& c : channels) h5->create_matrix("/curves/" + c, static_cast<std::size_t>(rows), T, std::nan(""));
  EvaluateResult result;
  result.qoi.resize(static_cast<std::size_t>(layout.qoi_count));
  auto compute = [&](int i) { return encode_record(i, model.run(x.row(i).data())); };
  auto consume = [&](TaskResult&& task) {
    const int index = task.index;
    const RunRecord r = decode_record(layout, std::move(task));
    result.failed += r.ok() ? 0 : 1;
    for (std::size_t q = 0; q < result.qoi.size(); ++q) result.qoi[q].push_back(r.qoi[q]);
    result.status.push_back(r.status);
    result.messages.push_back(r.message);
    if (r.ok() && h5 != nullptr)
      for (int c = 0; c < layout.channel_count; ++c)
        h5->write_row("/curves/" + channels[static_cast<std::size_t>(c)], static_cast<std::size_t>(index),
                      r.curve(c, layout.time_samples), T);
  };
  stream_study_tasks(rows, compute, consume, runtime.options);
  if (world_rank() != 0) return {};
  note_unsettled_rows(model, result);
  result.study = study;
  return result;
}

void write_evaluate(const EvaluateResult& result, io::Hdf5Writer& h5) {
  const EvaluateStudy& study = result.study;
  h5.write("/inputs/names", study.names);
  h5.write("/inputs/labels", study.design.columns);
  h5.write("/inputs/values", Eigen::MatrixXd(study.design.values));
  for (std::size_t q = 0; q < result.qoi.size(); ++q) h5.write("/qoi/" + study.request.qoi_names[q], result.qoi[q]);
  write_qoi_definitions(h5, study.model->qois());
  h5.write("/samples/status", result.status);
  h5.write("/samples/message", result.messages);
  if (!study.request.channel_names.empty()) h5.write("/t", study.model->time_s());
  h5.attribute("/", "study", "evaluate");
  h5.attribute("/", "scenario_file", study.request.scenario_path);
  h5.attribute("/", "scenario_json", study.model->sources().scenario.dump());
  h5.attribute("/", "rover_json", study.model->sources().rover.dump());
  h5.attribute("/", io::kTerrainDigestAttribute, io::terrain_digest(study.model->sources().terrain));
  const IntegratorSettings& integrator = study.model->nominal().scenario.integrator;  // --integrator's, if given
  write_integrator_provenance(h5, integrator);
  h5.attribute("/", "design_file", study.request.design_path);
  h5.attribute("/", "fingerprint", io::key_summary(study.fingerprint));
  h5.attribute("/", "project_version", ROVER_VERSION);
}

void write_evaluate_csv(const EvaluateResult& result, const std::string& path) {
  const EvaluateStudy& study = result.study;
  const DesignMatrix& x = study.design.values;
  const std::string partial = path + ".partial";
  io::create_temporary(partial, path);
  std::ofstream csv(partial, std::ios::binary | std::ios::trunc);
  if (!csv) throw std::runtime_error("cannot write " + partial);
  for (const std::string& c : study.design.columns) csv << c << ",";
  for (const std::string& q : study.request.qoi_names) csv << q << ",";
  csv << "status,message\n";
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const auto row = static_cast<std::size_t>(i);
    for (Eigen::Index j = 0; j < x.cols(); ++j) csv << exact_number_text(x(i, j)) << ",";
    for (const std::vector<double>& q : result.qoi) csv << exact_number_text(q[row]) << ",";
    csv << result.status[row] << "," << csv_quoted(result.messages[row]) << "\n";
  }
  csv.close();
  if (!csv) {
    std::filesystem::remove(partial);
    throw std::runtime_error("writing " + partial + " failed (disk full?)");
  }
  std::filesystem::rename(partial, path);
}

void plot_evaluate(const EvaluateResult& result, const std::string& results_path, PlotSelection plots) {
  if (plots == PlotSelection::kNone) return;
  const StudyModel& model = *result.study.model;
  std::vector<io::LinePlot> panels;
  for (std::size_t q = 0; q < result.qoi.size(); ++q) {
    std::vector<double> ok;
    for (std::size_t i = 0; i < result.status.size(); ++i)
      if (result.status[i] == run_status::kOk) ok.push_back(result.qoi[q][i]);
    if (auto h = histogram_panel(model.qoi_names()[q], model.qoi_units()[q], ok, nullptr, 0.0))
      panels.push_back(std::move(*h));
  }
  write_summary_figure("evaluate " + result.study.request.design_path + ": " +
                           std::to_string(result.status.size()) + " rows (" + std::to_string(result.failed) +
                           " failed)",
                       panels, sibling_path(results_path, "_summary.png"), "evaluate");
}

void report_evaluate(const EvaluateResult& result, std::ostream& out) {
  for (std::size_t q = 0; q < result.qoi.size(); ++q)
    if (const std::string w = qoi_values_warning(*result.study.model, q, result.qoi[q]); !w.empty())
      out << "evaluate: warning: " << w << "\n";
}

StudyProgram<EvaluateResult> evaluate_program(EvaluateStudy study) {
  StudyProgram<EvaluateResult> p;
  p.command = "evaluate";
  p.name = "evaluate";
  p.fingerprint = study.fingerprint;
  p.banner = std::to_string(study.design.values.rows()) + " rows of " + study.design.path + ", each a run of " +
             study.request.scenario_path + " on " + describe_integrator(study.model->nominal().scenario.integrator) +
             ", on " + std::to_string(world_size()) + " rank(s)";
  p.inputs = study.files;
  if (std::string coarse = coarse_recording_warning(study.model->qois(), study.model->nominal().scenario.output_rate_hz);
      !coarse.empty())
    p.warnings.push_back(std::move(coarse));
  p.run = [study](const StudyRuntime& runtime) { return run_evaluate(study, runtime); };
  p.write = write_evaluate;
  p.write_csv = write_evaluate_csv;
  p.plot = plot_evaluate;
  p.figures = [](PlotSelection plots) {
    return plots == PlotSelection::kNone ? std::vector<PlannedFigure>{}
                                         : std::vector<PlannedFigure>{{"_summary.png", "the summary"}};
  };
  p.report = report_evaluate;
  p.counts = [](const EvaluateResult& r) { return count_runs(r.status, r.messages); };
  p.status_when_some_failed = kSomeRunsFailedStatus;
  return p;
}

}  // namespace rover::study
