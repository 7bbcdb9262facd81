// Numeric CSV tables: measured data in (calibration targets, terrain
// profiles), small result tables out.
//
// Format read: a header line of column names, then one line of numbers per row,
// comma-separated; blank lines and '#' comments (whole-line or trailing) are
// ignored; surrounding spaces and Windows line ends are accepted. Every value
// must be a finite number. Errors name the file and the line:
// "data.csv:17: expected 2 values, got 3".
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace rover::io {

struct CsvTable {
  std::vector<std::string> header;           // column names, in file order
  std::vector<std::vector<double>> columns;  // columns[j][row] belongs to header[j]

  std::size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
  // The column named `name`; throws std::runtime_error listing the columns if absent.
  const std::vector<double>& column(const std::string& name) const;
};

// Reads a CSV file; throws ConfigError (io/json_reader.hpp) on a missing file, an
// empty file, a malformed line, a header without one of `required_columns`, or
// a file without data rows.
CsvTable read_csv(const std::string& path, const std::vector<std::string>& required_columns = {});

// Writes columns (all of one length) under `header`, atomically (temp file +
// rename). Values are written in the shortest form that reads back exactly
// (non-finite values as nan/inf, which read_csv refuses). A nonempty `comment`
// is written first, each of its lines prefixed with "# ".
void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<double>>& columns, const std::string& comment = "");

}  // namespace rover::io
