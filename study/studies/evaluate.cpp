// See evaluate.hpp.
#include "study/studies/evaluate.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>

#include "io/hdf5_file.hpp"
#include "io/json_reader.hpp"
#include "study/studies/study_output.hpp"
#include "study/runtime/study_runner.hpp"
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

// The shortest text that reads back to exactly x.
std::string number(double x) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, x);
  return std::string(text, result.ptr);
}

}  // namespace

DesignTable read_design_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path)) throw io::ConfigError(path + ": cannot read the design file");
  DesignTable table;
  table.path = path;
  std::string line;
  std::vector<std::vector<double>> rows;
  int line_number = 0;
  bool header = true;
  while (std::getline(in, line)) {
    ++line_number;
    if (line_number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    if (trim(line).empty()) continue;
    const std::vector<std::string> cells = split_commas(line);
    const std::string where = path + ":" + std::to_string(line_number);
    if (header) {
      table.columns = cells;
      table.header_line = line_number;
      for (std::size_t j = 0; j < cells.size(); ++j)
        if (cells[j].empty()) throw io::ConfigError(where + ": column " + std::to_string(j + 1) + " has no name");
      header = false;
      continue;
    }
    if (cells.size() != table.columns.size())
      throw io::ConfigError(where + ": expected " + std::to_string(table.columns.size()) + " values, got " +
                            std::to_string(cells.size()));
    std::vector<double> row;
    for (std::size_t j = 0; j < cells.size(); ++j) {
      std::size_t used = 0;
      double v = std::nan("");
      try {
        v = std::stod(cells[j], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != cells[j].size() || !std::isfinite(v))
        throw io::ConfigError(where + ": column " + std::to_string(j + 1) + " (" + table.columns[j] +
                              "): '" + cells[j] + "' is not a finite number");
      row.push_back(v);
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

int run_evaluate(const EvaluateRequest& request) {
  const bool root = world_rank() == 0;
  const std::string& out = request.out_path;
  const bool to_csv = out.ends_with(".csv");
  if (!to_csv && !out.ends_with(".h5")) throw std::invalid_argument("--out must end in .csv or .h5, got '" + out + "'");
  if (std::filesystem::is_directory(out)) throw std::invalid_argument("--out '" + out + "' is a directory");
  if (to_csv && !request.channel_names.empty())
    throw std::invalid_argument("--channels needs an .h5 output (curves do not fit a CSV row)");

  io::ScenarioSources sources = io::read_scenario_sources(request.scenario_path);
  const DesignTable design = read_design_csv(request.design_path);
  const ParameterSpace space(sources.rover, sources.scenario);
  std::vector<std::string> names;
  for (std::size_t j = 0; j < design.columns.size(); ++j) {
    try {
      names.push_back(space.canonical(design.columns[j]));
    } catch (const std::invalid_argument& e) {
      throw io::ConfigError(design.path + ":" + std::to_string(design.header_line) +
                            ": column " + std::to_string(j + 1) + ": " + e.what());
    }
    for (std::size_t k = 0; k < j; ++k)
      if (names[k] == names[j])
        throw io::ConfigError(design.path + ": columns " + std::to_string(k + 1) + " and " + std::to_string(j + 1) +
                              " name the same parameter (" + names[j] + ")");
  }
  std::vector<QoiSpec> qois;
  for (const std::string& q : request.qoi_names) {
    QoiSpec spec;
    spec.name = q;
    spec.kind = qoi_kind_from_name(q);
    if (spec.kind == QoiKind::kRmsVs)
      throw std::invalid_argument("--qoi rms_vs needs a reference curve: use a montecarlo study file for it");
    qois.push_back(spec);
  }
  std::vector<Channel> channels;
  for (const std::string& c : request.channel_names) channels.push_back(channel_from_name(c));
  std::optional<IntegratorSettings> integrator;
  if (!request.integrator.empty())
    integrator = default_integrator_settings(integrator_from_name(request.integrator));
  const RoverStudyModel model(sources, names, qois, channels, integrator);

  // Every row is checked before any run starts.
  const auto rows = static_cast<int>(design.values.rows());
  if (root)
    for (int i = 0; i < rows; ++i) {
      try {
        (void)model.setup_at(design.values.row(i).data());
      } catch (const std::exception& e) {
        throw io::ConfigError(design.path + ":" + std::to_string(design.line_numbers[static_cast<std::size_t>(i)]) +
                              ": this row's values are not a valid configuration: " + e.what());
      }
    }

  const RecordLayout layout = model.layout();
  std::unique_ptr<io::Hdf5Writer> h5;
  std::ofstream csv;
  const std::string partial = out + ".partial";
  if (root) {
    if (const auto dir = std::filesystem::path(out).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
    if (to_csv) {
      csv.open(partial, std::ios::binary | std::ios::trunc);
      if (!csv) throw std::runtime_error("cannot write " + partial);
      for (const std::string& c : design.columns) csv << c << ",";
      for (const std::string& q : request.qoi_names) csv << q << ",";
      csv << "status,message\n";
    } else {
      h5 = std::make_unique<io::Hdf5Writer>(out);
      for (const std::string& c : request.channel_names)
        h5->create_matrix("/curves/" + c, static_cast<std::size_t>(rows), static_cast<std::size_t>(layout.time_samples),
                          std::nan(""));
    }
  }
  std::vector<std::vector<double>> qoi_values(qois.size());
  std::vector<int> status;
  std::vector<std::string> messages;
  int failed = 0;
  auto compute = [&](int i) { return encode_record(i, model.run(design.values.row(i).data())); };
  auto consume = [&](TaskResult&& task) {
    const int index = task.index;
    const RunRecord r = decode_record(layout, std::move(task));
    failed += r.ok() ? 0 : 1;
    if (to_csv) {
      for (Eigen::Index j = 0; j < design.values.cols(); ++j) csv << number(design.values(index, j)) << ",";
      for (double q : r.qoi) csv << number(q) << ",";
      csv << r.status << "," << csv_quoted(r.message) << "\n";
      if (!csv) throw std::runtime_error("writing " + partial + " failed (disk full?)");
    } else {
      for (std::size_t q = 0; q < qois.size(); ++q) qoi_values[q].push_back(r.qoi[q]);
      status.push_back(r.status);
      messages.push_back(r.message);
      if (r.ok())
        for (int c = 0; c < layout.channel_count; ++c)
          h5->write_row("/curves/" + request.channel_names[static_cast<std::size_t>(c)], static_cast<std::size_t>(index),
                        r.curve(c, layout.time_samples), static_cast<std::size_t>(layout.time_samples));
    }
  };
  std::string fingerprint = io::config_fingerprint(file_text(request.design_path) + file_text(request.scenario_path) +
                                                   file_text(sources.rover_path) + file_text(sources.terrain_path) +
                                                   "|qoi:" + [&] {
                                                     std::string s;
                                                     for (const auto& q : request.qoi_names) s += q + ",";
                                                     for (const auto& c : request.channel_names) s += c + ";";
                                                     return s + "|integrator:" + request.integrator;
                                                   }());
  StudyRunOptions options{out, fingerprint, request.resume, "evaluate", request.progress_interval_s,
                          request.resume_command, io::CheckpointPolicy{}};
  try {
    stream_study_tasks(rows, compute, consume, options);
  } catch (...) {
    if (csv.is_open()) {
      csv.close();
      std::filesystem::remove(partial);
    }
    throw;
  }
  if (!root) return failed;
  if (to_csv) {
    csv.close();
    if (!csv) throw std::runtime_error("writing " + partial + " failed (disk full?)");
    std::filesystem::rename(partial, out);
  } else {
    h5->write("/inputs/names", names);
    h5->write("/inputs/labels", design.columns);
    h5->write("/inputs/values", Eigen::MatrixXd(design.values));
    for (std::size_t q = 0; q < qois.size(); ++q) h5->write("/qoi/" + qois[q].name, qoi_values[q]);
    h5->write("/samples/status", status);
    h5->write("/samples/message", messages);
    if (!channels.empty()) h5->write("/t", model.time_s());
    h5->attribute("/", "study", "evaluate");
    h5->attribute("/", "scenario_file", request.scenario_path);
    h5->attribute("/", "design_file", request.design_path);
    h5->attribute("/", "fingerprint", fingerprint);
    h5->attribute("/", "project_version", ROVER_VERSION);
    h5->commit();
  }
  remove_checkpoint(out);
  std::cerr << "evaluate: " << rows << " runs (" << failed << " failed), wrote " << out << "\n";
  return failed;
}

}  // namespace rover::study
