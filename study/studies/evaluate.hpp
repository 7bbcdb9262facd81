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
//
// The study's parts, run by the study driver (study_driver.hpp):
// load_evaluate() (the flags, the scenario and every design row checked),
// run_evaluate() (the runs; curves streamed into the HDF5 file),
// write_evaluate() or write_evaluate_csv(), report_evaluate() and plot_evaluate().
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <memory>

#include "io/hdf5_file.hpp"
#include "study/design/design.hpp"
#include "study/model/study_model.hpp"
#include "study/studies/study_driver.hpp"

namespace rover::study {

struct DesignTable {
  std::string path;
  std::vector<std::string> columns;  // as written
  DesignMatrix values;               // rows x columns
  std::vector<int> line_numbers;     // the file line of each row
  int header_line = 1;
};

// Reads a design CSV (throws io::ConfigError naming file, line and column).
// `check_columns`, if given, sees the table once its header is read, before
// any value: a column that names no input is refused before its cells are.
DesignTable read_design_csv(const std::string& path,
                            const std::function<void(const DesignTable&)>& check_columns = {});

struct EvaluateRequest {
  std::string scenario_path, design_path, out_path;
  std::vector<std::string> qoi_names;      // plain QoI names
  std::vector<std::string> channel_names;  // optional, .h5 output only
  std::string integrator;                  // optional method name
};

struct EvaluateStudy {
  EvaluateRequest request;
  DesignTable design;
  std::vector<std::string> names;  // the canonical parameter of each design column
  std::shared_ptr<const RoverStudyModel> model;
  std::string fingerprint;         // design, scenario, rover, terrain, QoIs, channels, integrator
  io::InputFiles files;            // --design, --scenario and the files the scenario names
};

// Reads the scenario and the design and checks every row (rank 0) before any
// run. Throws std::invalid_argument for curves asked into a CSV,
// io::ConfigError naming the file, line and column for a bad design.
EvaluateStudy load_evaluate(const EvaluateRequest& request);

// Per design row, in row order.
struct EvaluateResult {
  EvaluateStudy study;
  std::vector<std::vector<double>> qoi;  // [qoi][row]
  std::vector<int> status;
  std::vector<std::string> messages;
  int failed = 0;
};

// Collective over MPI ranks; on rank 0 the curves go into runtime.h5 (HDF5
// output only) as the runs arrive. The result is meaningful on rank 0.
EvaluateResult run_evaluate(const EvaluateStudy& study, const StudyRuntime& runtime);

void write_evaluate(const EvaluateResult& result, io::Hdf5Writer& h5);
// The CSV: a header row, then one row per design row (inputs as given, QoIs,
// status, message), written to "<path>.partial" and renamed into place.
void write_evaluate_csv(const EvaluateResult& result, const std::string& path);

// The console report: a warning for each QoI whose values do not mean what
// its name says (qoi_values_warning: settling times that never came).
void report_evaluate(const EvaluateResult& result, std::ostream& out);

// <results>_summary.png: a histogram of each QoI over the successful rows.
void plot_evaluate(const EvaluateResult& result, const std::string& results_path, PlotSelection plots);

// The study as the driver runs it: exit status 2 when any run failed.
StudyProgram<EvaluateResult> evaluate_program(EvaluateStudy study);

}  // namespace rover::study
