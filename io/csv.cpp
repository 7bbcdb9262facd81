// See csv.hpp.
#include "io/csv.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include "io/json_reader.hpp"

namespace rover::io {
namespace {

std::string_view trim(std::string_view s) {
  const std::size_t begin = s.find_first_not_of(" \t\r");
  if (begin == std::string_view::npos) return {};
  const std::size_t end = s.find_last_not_of(" \t\r");
  return s.substr(begin, end - begin + 1);
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

}  // namespace

const std::vector<double>& CsvTable::column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end())
    throw std::runtime_error("CSV table: no column '" + name + "' (columns: " + join(header) + ")");
  return columns[static_cast<std::size_t>(it - header.begin())];
}

CsvTable read_csv(const std::string& path, const std::vector<std::string>& required_columns) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open file");
  CsvTable table;
  std::size_t header_line = 0, line_number = 0;
  std::string line;
  while (std::getline(in, line)) {
    ++line_number;
    std::string_view content(line);
    content = trim(content.substr(0, content.find('#')));
    if (content.empty()) continue;
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    const std::vector<std::string_view> fields = split_fields(content);

    if (header_line == 0) {  // the first content line is the header
      header_line = line_number;
      std::set<std::string> seen;
      for (std::string_view field : fields) {
        if (field.size() >= 2 && field.front() == '"' && field.back() == '"')
          field = trim(field.substr(1, field.size() - 2));
        std::string name(field);
        if (name.empty()) throw ConfigError(where + "empty column name in the header");
        if (!seen.insert(name).second) throw ConfigError(where + "duplicate column '" + name + "'");
        table.header.push_back(std::move(name));
      }
      for (const std::string& required : required_columns)
        if (!seen.count(required))
          throw ConfigError(where + "missing column '" + required +
                            "' (columns: " + join(table.header) + ")");
      table.columns.resize(table.header.size());
      continue;
    }

    if (fields.size() != table.header.size())
      throw ConfigError(where + "expected " + std::to_string(table.header.size()) +
                        " values, got " + std::to_string(fields.size()));
    for (std::size_t j = 0; j < fields.size(); ++j) {
      const std::string_view field = fields[j];
      const std::string column = "column '" + table.header[j] + "': ";
      if (field.empty()) throw ConfigError(where + column + "empty value");
      // from_chars does not take a leading '+'.
      const std::string_view digits = field.front() == '+' ? field.substr(1) : field;
      double value = 0.0;
      const auto [end, error] =
          std::from_chars(digits.data(), digits.data() + digits.size(), value);
      if (error == std::errc::result_out_of_range && end == digits.data() + digits.size())
        throw ConfigError(where + column + "'" + std::string(field) + "' is out of range");
      if (error != std::errc() || end != digits.data() + digits.size() || digits.empty())
        throw ConfigError(where + column + "'" + std::string(field) + "' is not a number");
      if (!std::isfinite(value))
        throw ConfigError(where + column + "'" + std::string(field) + "' is not a finite number");
      table.columns[j].push_back(value);
    }
  }
  if (in.bad()) throw ConfigError(path + ": read error");
  if (header_line == 0) throw ConfigError(path + ": empty file (no header line)");
  if (table.rows() == 0)
    throw ConfigError(path + ":" + std::to_string(header_line) + ": no data rows after the header");
  return table;
}

void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<double>>& columns, const std::string& comment) {
  if (columns.size() != header.size())
    throw std::invalid_argument(path + ": " + std::to_string(header.size()) + " column names for " +
                                std::to_string(columns.size()) + " columns");
  for (const std::string& name : header)
    if (name.empty() || name.find_first_of(",#\n\r\"") != std::string::npos ||
        trim(name).size() != name.size())
      throw std::invalid_argument(path + ": column name '" + name + "' cannot be written to CSV");
  const std::size_t rows = columns.empty() ? 0 : columns.front().size();
  for (std::size_t j = 0; j < columns.size(); ++j)
    if (columns[j].size() != rows)
      throw std::invalid_argument(path + ": column '" + header[j] + "' has " +
                                  std::to_string(columns[j].size()) + " values, column '" +
                                  header[0] + "' has " + std::to_string(rows));

  const std::string partial = path + ".partial";
  {
    std::ofstream out(partial, std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot create '" + partial + "'");
    std::istringstream comment_lines(comment);
    for (std::string line; std::getline(comment_lines, line);) out << "# " << line << '\n';
    for (std::size_t j = 0; j < header.size(); ++j) out << (j ? "," : "") << header[j];
    out << '\n';
    std::array<char, 32> buffer{};
    for (std::size_t i = 0; i < rows; ++i) {
      for (std::size_t j = 0; j < columns.size(); ++j) {
        const auto result =
            std::to_chars(buffer.data(), buffer.data() + buffer.size(), columns[j][i]);
        if (j) out << ',';
        out.write(buffer.data(), result.ptr - buffer.data());
      }
      out << '\n';
    }
    out.close();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(partial, ignored);
      throw std::runtime_error(path + ": cannot write '" + partial + "'");
    }
  }
  std::error_code error;
  std::filesystem::rename(partial, path, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(partial, ignored);
    throw std::runtime_error(path + ": cannot rename '" + partial + "': " + error.message());
  }
}

}  // namespace rover::io
