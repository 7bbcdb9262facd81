// Batch evaluation: the interface other tools (Dakota's fork interface,
// OpenTURNS, SALib, UQLab, a Python script) drive the model through. Every row
// of a design CSV is one run with the named inputs (every other parameter at
// its configured value); the output has, in row order, the inputs, each QoI,
// the status and the message of every run.
//
// Design CSV: a header of parameter names (study/model/parameter_space.hpp: dotted
// config paths or the aliases f, c_q, M0_11 .. M0_42), then one row of numbers
// per run; '#' comments and blank lines are skipped, a UTF-8 byte-order mark is
// accepted. Every row is checked before any run: an unknown column, a
// non-numeric cell or a value outside its parameter's valid range is an error
// naming the file, the line and the column.
//
// Output: .csv (header: inputs..., qois..., status, message) or .h5
// (/inputs/names, /inputs/values, /qoi/<name>, /samples/status,
// /samples/message, /t and /curves/<channel> when channels are asked for).
#pragma once

#include <string>
#include <vector>

#include "study/design/design.hpp"
#include "study/model/study_model.hpp"

namespace rover::study {

struct DesignTable {
  std::string path;
  std::vector<std::string> columns;  // as written
  DesignMatrix values;               // rows x columns
  std::vector<int> line_numbers;     // the file line of each row
  int header_line = 1;
};

// Reads a design CSV (throws io::ConfigError naming file, line and column).
DesignTable read_design_csv(const std::string& path);

struct EvaluateRequest {
  std::string scenario_path, design_path, out_path;
  std::vector<std::string> qoi_names;      // plain QoI names
  std::vector<std::string> channel_names;  // optional, .h5 output only
  std::string integrator;                  // optional method name
  bool resume = false;
  int progress_interval_s = 5;
  std::string resume_command;
};

// Collective over MPI ranks; rank 0 writes the output. Returns the number of
// failed runs.
int run_evaluate(const EvaluateRequest& request);

}  // namespace rover::study
