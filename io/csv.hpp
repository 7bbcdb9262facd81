// Numeric CSV tables: measured data in (calibration targets, terrain
// profiles), small result tables out.
//
// Format read: a header line of column names, then one line of numbers per row,
// comma-separated; blank lines and '#' comments (whole-line or trailing) are
// ignored; surrounding spaces, Windows line ends and a UTF-8 byte-order mark
// (as spreadsheet programs write) are accepted, and so are names and values in
// double quotes ("c_q", "0.25"). Every value must be a finite number. Errors name the file and the line (never a row index):
// "data.csv:17: expected 2 values, got 3".
//
// Measured curves t,z (drop tests: time [s], height [m] of the left bogie pin)
// are read by read_measured_curve(), the one check shared by every command
// that takes such data.
#pragma once

#include <atomic>

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace rover::io {

struct CsvTable {
  std::string path;                          // the file read, for messages
  std::vector<std::string> header;           // column names, in file order
  std::vector<std::vector<double>> columns;  // columns[j][row] belongs to header[j]
  std::vector<std::size_t> line_numbers;     // line_numbers[row]: its line in the file (1-based)

  std::size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
  // The column named `name`; throws ConfigError naming the file and listing
  // the columns if absent.
  const std::vector<double>& column(const std::string& name) const;
  // "path:line" of a data row, the prefix of messages about it.
  std::string where(std::size_t row) const;
};

// Reads a CSV file; throws ConfigError (io/json_reader.hpp) on a missing file, a
// directory, an empty file, a malformed line, a header without one of
// `required_columns`, or a file without data rows.
CsvTable read_csv(const std::string& path, const std::vector<std::string>& required_columns = {});

// A cell as RFC 4180 quotes it ("c_q", "0.25", or "a""b" for a"b), unquoted;
// any other cell as it is.
std::string unquoted_csv_cell(std::string_view cell);

// An unquoted header name holding a tab or a semicolon: the file is
// separated by that character, not by commas; what to do. Empty when the
// name is an ordinary one.
std::string csv_separator_problem(std::string_view header_name);

// A sampled curve: strictly increasing times and finite values.
struct MeasuredCurve {
  std::vector<double> t_s;
  std::vector<double> z_m;
};

inline constexpr std::size_t kMeasuredCurveMinRows = 3;
// |z| of a measured height above this is a unit or column mistake (mm for m).
inline constexpr double kMeasuredCurveMaxAbsHeight_m = 1e3;

// Reads a measured curve: a CSV file with columns "t" [s] and "z" [m] (others
// are ignored) holding at least kMeasuredCurveMinRows rows, strictly
// increasing times and |z| < kMeasuredCurveMaxAbsHeight_m. Throws ConfigError
// naming the file, the line and the value otherwise.
MeasuredCurve read_measured_curve(const std::string& path);

// The channel a measured curve's header declares for its z column, as
// `rover synthesize` writes it ("# Columns: t [s], z [m] = B_r_z, ..."), or
// "" when the file declares none (a file from elsewhere, or not a CSV) or is
// no regular file (which is not read: its reader refuses it).
std::string declared_channel(const std::string& path);

// The checks of read_measured_curve() on columns "t" and `value_column` of a
// table, with |value| < max_abs_value (infinity: no bound); read_measured_curve
// is curve_from_table(read_csv(path, {"t", "z"}), "z", kMeasuredCurveMaxAbsHeight_m).
MeasuredCurve curve_from_table(const CsvTable& table, const std::string& value_column,
                               double max_abs_value);

// Writes columns (all of one length) under `header`, atomically (temp file +
// rename) to a regular file; a device, a pipe or an open descriptor such as
// /dev/stdout is appended to in place, and a link or a read-only file is
// refused (io/output_target.hpp). Every write
// and the close are checked: a full disk throws std::runtime_error naming the
// file, and leaves no partial file. Values are written in the shortest form that reads back exactly
// (non-finite values as nan/inf, which read_csv refuses). A nonempty `comment`
// is written first, each of its lines prefixed with "# ".
// `stop` (if given) is read every kStopCheckRows rows of a regular file: once
// it is set, the temporary is removed and false is returned, the file at
// `path` left as it was (a signal's request to stop); true otherwise. A
// write to a device or pipe that fails once `stop` is set (a closed pipe's
// SIGPIPE) also returns false.
inline constexpr std::size_t kStopCheckRows = 4096;
bool write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<double>>& columns, const std::string& comment = "",
               const std::atomic<bool>* stop = nullptr);

}  // namespace rover::io
