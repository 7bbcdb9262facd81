// See csv.hpp.
#include "io/csv.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include "io/decimal_number.hpp"
#include "io/json_reader.hpp"
#include "io/output_target.hpp"
#include "io/text_encoding.hpp"

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

// The shortest text that reads back as x.
std::string shortest_text(double x) {
  std::array<char, 32> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), x);
  return std::string(buffer.data(), result.ptr);
}

constexpr std::string_view kUtf8ByteOrderMark = "\xEF\xBB\xBF";

// While alive, holds a pipe at `path` open for writing without waiting; throws
// std::runtime_error when no process has it open for reading. Anything other
// than a pipe is left alone.
class PipeProbe {
 public:
  explicit PipeProbe(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || !S_ISFIFO(st.st_mode)) return;
    fd_ = ::open(path.c_str(), O_WRONLY | O_NONBLOCK);
    if (fd_ < 0 && errno == ENXIO)
      throw std::runtime_error(path + ": a pipe that no process reads; writing would wait forever: start its "
                               "reader first (cat " + path + " &), or give a file name");
  }
  ~PipeProbe() {
    if (fd_ >= 0) ::close(fd_);
  }
  PipeProbe(const PipeProbe&) = delete;
  PipeProbe& operator=(const PipeProbe&) = delete;

 private:
  int fd_ = -1;
};

// Writes header and rows to `out`; false if any write failed.
bool write_rows(std::ostream& out, const std::vector<std::string>& header,
                const std::vector<std::vector<double>>& columns, std::size_t rows, const std::string& comment,
                const std::atomic<bool>* stop = nullptr) {
  std::istringstream comment_lines(comment);
  for (std::string line; std::getline(comment_lines, line);) out << "# " << line << '\n';
  for (std::size_t j = 0; j < header.size(); ++j) out << (j ? "," : "") << header[j];
  out << '\n';
  std::array<char, 32> buffer{};
  for (std::size_t i = 0; i < rows && out; ++i) {
    if (stop != nullptr && i % kStopCheckRows == 0 && stop->load()) return false;
    for (std::size_t j = 0; j < columns.size(); ++j) {
      const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), columns[j][i]);
      if (j) out << ',';
      out.write(buffer.data(), result.ptr - buffer.data());
    }
    out << '\n';
  }
  out.flush();
  return static_cast<bool>(out);
}

// write_rows to a file, then closed; false if any write or the close failed,
// or `stop` was set.
bool write_table(std::ofstream& out, const std::vector<std::string>& header,
                 const std::vector<std::vector<double>>& columns, std::size_t rows,
                 const std::string& comment, const std::atomic<bool>* stop = nullptr) {
  const bool written = write_rows(out, header, columns, rows, comment, stop);
  out.close();
  return written && static_cast<bool>(out);
}

// write_rows through this process's open descriptor `fd` (io::own_descriptor),
// after what the program's own streams hold, so that the table shares the
// descriptor's offset and order with the console lines.
void write_table_to_descriptor(int fd, const std::string& path, const std::vector<std::string>& header,
                               const std::vector<std::vector<double>>& columns, std::size_t rows,
                               const std::string& comment) {
  std::ostringstream text;
  write_rows(text, header, columns, rows, comment);
  std::cout.flush();
  std::cerr.flush();
  const std::string bytes = text.str();
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw std::runtime_error(path + ": cannot write" + (errno != 0 ? std::string(" (") + std::strerror(errno) + ")" : ""));
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace

const std::vector<double>& CsvTable::column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end())
    throw ConfigError((path.empty() ? std::string("CSV table") : path) + ": no column '" + name +
                      "' (columns: " + join(header) + ")");
  return columns[static_cast<std::size_t>(it - header.begin())];
}

std::string CsvTable::where(std::size_t row) const {
  return path + ":" + (row < line_numbers.size() ? std::to_string(line_numbers[row]) : "?");
}

CsvTable read_csv(const std::string& path, const std::vector<std::string>& required_columns) {
  if (const std::string problem = input_path_problem(path, "a CSV file"); !problem.empty())
    throw ConfigError(path + ": " + problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot open file");
  CsvTable table;
  table.path = path;
  std::size_t header_line = 0, line_number = 0;
  std::string line;
  while (std::getline(in, line)) {
    ++line_number;
    std::string_view content(line);
    if (const std::string problem = text_encoding_problem(content); !problem.empty())
      throw ConfigError(path + ":" + std::to_string(line_number) + ": " + problem +
                        ": save a CSV file as UTF-8 (plain text)");
    if (const std::string problem = line_ending_problem(content); !problem.empty())
      throw ConfigError(path + ":" + std::to_string(line_number) + ": " + problem);
    if (line_number == 1 && content.substr(0, kUtf8ByteOrderMark.size()) == kUtf8ByteOrderMark)
      content.remove_prefix(kUtf8ByteOrderMark.size());
    content = trim(content.substr(0, content.find('#')));
    if (content.empty()) continue;
    const std::string where = path + ":" + std::to_string(line_number) + ": ";
    const std::vector<std::string_view> fields = split_fields(content);

    if (header_line == 0) {  // the first content line is the header
      header_line = line_number;
      std::set<std::string> seen;
      for (std::string_view field : fields) {
        const bool quoted = field.size() >= 2 && field.front() == '"' && field.back() == '"';
        if (!quoted)
          if (const std::string problem = csv_separator_problem(field); !problem.empty()) throw ConfigError(where + problem);
        std::string name = quoted ? std::string(trim(unquoted_csv_cell(field))) : std::string(field);
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
      // A value quoted as spreadsheets write every cell ("0.25") reads as the number.
      const std::string unquoted = unquoted_csv_cell(fields[j]);
      const std::string_view field = trim(unquoted);
      const std::string column = "column '" + table.header[j] + "': ";
      if (field.empty()) throw ConfigError(where + column + "empty value");
      const DecimalNumber number = parse_decimal_number(field);
      if (number.status == DecimalStatus::kOutOfRange)
        throw ConfigError(where + column + "'" + std::string(field) + "' is out of range");
      if (number.status == DecimalStatus::kNotFinite)
        throw ConfigError(where + column + "'" + std::string(field) + "' is not a finite number");
      if (number.status != DecimalStatus::kOk) {
        const std::string hint = decimal_number_hint(field);
        throw ConfigError(where + column + "'" + std::string(field) + "' is not a number" +
                          (hint.empty() ? "" : ": " + hint));
      }
      table.columns[j].push_back(number.value);
    }
    table.line_numbers.push_back(line_number);
  }
  if (in.bad()) throw ConfigError(path + ": read error");
  if (header_line == 0) throw ConfigError(path + ": empty file (no header line)");
  if (table.rows() == 0)
    throw ConfigError(path + ":" + std::to_string(header_line) + ": no data rows after the header");
  return table;
}

bool write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<double>>& columns, const std::string& comment,
               const std::atomic<bool>* stop) {
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

  namespace fs = std::filesystem;
  const auto system_reason = [] { return errno != 0 ? std::string(" (") + std::strerror(errno) + ")" : ""; };
  if (require_output(path, OutputFormat::kText) == OutputMode::kStream) {
    // A device, a pipe or an open descriptor: no temporary file next to it,
    // and no rename over it; appended to, as a shell's `>>` would.
    // A pipe no process reads would block the open forever: refused. The
    // probe stays open until the stream is, so a reader never sees an end.
    const PipeProbe probe(path);
    // A write that failed because its reader has gone (EPIPE) after a signal
    // was raised (the SIGPIPE of that write) is the signal's stop.
    const auto stopped = [&] { return stop != nullptr && stop->load(); };
    errno = 0;
    if (const int fd = own_descriptor(path); fd >= 0) {
      try {
        write_table_to_descriptor(fd, path, header, columns, rows, comment);
      } catch (const std::runtime_error&) {
        if (stopped()) return false;
        throw;
      }
      return true;
    }
    std::ofstream out(path, std::ios::app);
    if (!out) throw std::runtime_error(path + ": cannot open for writing" + system_reason());
    if (!write_table(out, header, columns, rows, comment)) {
      if (stopped()) return false;
      throw std::runtime_error(path + ": cannot write" + system_reason());
    }
    return true;
  }

  const std::string partial = path + ".partial";
  create_temporary(partial, path);
  errno = 0;
  std::ofstream out(partial, std::ios::trunc);
  if (!out) throw std::runtime_error(path + ": cannot create '" + partial + "'" + system_reason());
  if (!write_table(out, header, columns, rows, comment, stop)) {
    const std::string reason = system_reason();
    std::error_code ignored;
    fs::remove(partial, ignored);
    if (stop != nullptr && stop->load()) return false;
    throw std::runtime_error(path + ": cannot write '" + partial + "'" + reason);
  }
  std::error_code error;
  fs::rename(partial, path, error);
  if (error) {
    std::error_code ignored;
    fs::remove(partial, ignored);
    throw std::runtime_error(path + ": cannot rename '" + partial + "': " + error.message());
  }
  return true;
}

MeasuredCurve curve_from_table(const CsvTable& table, const std::string& value_column,
                               double max_abs_value) {
  const std::vector<double>& t = table.column("t");
  const std::vector<double>& value = table.column(value_column);
  if (table.rows() < kMeasuredCurveMinRows)
    throw ConfigError(table.path + ": " + std::to_string(table.rows()) +
                      " data row(s); a curve needs at least " +
                      std::to_string(kMeasuredCurveMinRows));
  for (std::size_t row = 0; row < table.rows(); ++row) {
    // read_csv has refused non-finite values already.
    if (!(std::abs(value[row]) < max_abs_value))
      throw ConfigError(table.where(row) + ": column '" + value_column + "': " +
                        shortest_text(value[row]) + " is beyond the bound |" + value_column +
                        "| < " + shortest_text(max_abs_value) + " (metres expected)");
    if (row > 0 && !(t[row] > t[row - 1]))
      throw ConfigError(table.where(row) + ": column 't': " + shortest_text(t[row]) +
                        " does not follow " + shortest_text(t[row - 1]) + " (line " +
                        std::to_string(table.line_numbers[row - 1]) +
                        "); times must increase strictly");
  }
  return {t, value};
}

MeasuredCurve read_measured_curve(const std::string& path) {
  return curve_from_table(read_csv(path, {"t", "z"}), "z", kMeasuredCurveMaxAbsHeight_m);
}

std::string declared_channel(const std::string& path) {
  constexpr std::string_view kDeclaration = "z [m] = ";
  constexpr int kHeaderLinesRead = 32;  // the declaration stands in the leading comment block
  if (!input_path_problem(path, "a CSV file").empty()) return "";  // its reader refuses it (a pipe: unread)
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int k = 0; k < kHeaderLinesRead && std::getline(in, line); ++k) {
    if (k == 0 && line.starts_with(kUtf8ByteOrderMark)) line.erase(0, kUtf8ByteOrderMark.size());  // as read_csv
    if (!line.starts_with("#")) break;
    const std::size_t at = line.find(kDeclaration);
    if (at == std::string::npos) continue;
    // A name, then a comma: "= B_r_z, the world z ..." (a description, "= world z of ...", names none).
    const std::size_t start = at + kDeclaration.size(), end = line.find_first_of(",. ", start);
    return end != std::string::npos && line[end] == ',' ? line.substr(start, end - start) : "";
  }
  return "";
}

std::string unquoted_csv_cell(std::string_view cell) {
  if (cell.size() < 2 || cell.front() != '"' || cell.back() != '"') return std::string(cell);
  std::string name;
  for (std::size_t k = 1; k + 1 < cell.size(); ++k) {
    name += cell[k];
    if (cell[k] == '"' && cell[k + 1] == '"') ++k;
  }
  return name;
}

std::string csv_separator_problem(std::string_view name) {
  const bool tab = name.find('\t') != std::string_view::npos;
  if (!tab && name.find(';') == std::string_view::npos) return "";
  std::string shown;
  for (const char c : name) shown += c == '\t' ? std::string("\\t") : std::string(1, c);
  return std::string("the header '") + shown + "' is separated by " + (tab ? "tabs" : "semicolons ';'") +
         ": rover reads comma-separated values only; save the file with commas between the columns "
         "(and '.' as the decimal point)";
}

}  // namespace rover::io
