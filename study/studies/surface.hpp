// Response surfaces over (f, c_q) (paper section 3.5, Fig. 13a-c): at each
// grid point the RMS of B_l z against a reference drop curve and the
// computation time t_c of the run; plus the one-dimensional sweep of t_c over
// f with its linear regression t_c = a + b f (Fig. 13a).
//
// Study file (configs/studies/f_cq_surface.json):
//   {"type": "surface", "name": "f_cq_surface", "scenario": "../scenarios/drop_horizontal.json",
//    "reference": {"file": "../data/drop_horizontal_synthetic.csv", "time_offset": 0.0}
//              or {"simulate": {"f": 1e4, "c_q": 0.14}},
//    "f":   {"min": 1e2, "max": 1e5, "count": 7, "spacing": "log"},
//    "c_q": {"min": 0.05, "max": 0.5, "count": 6, "spacing": "linear"},
//    "sweep": {"f": {"min": 1e2, "max": 1e5, "count": 8, "spacing": "log"}, "c_q": 0.14},
//    "integrator": {...optional...}}
// With "surrogate": "gp" the surface is predicted by kriging from "runs"
// runs of a Latin hypercube instead of run on the grid (surface_kriging.hpp).
// A reference file is CSV "t,z" or an HDF5 trajectory; time_offset is
// subtracted from its times (measured curves rarely start at the release).
//
// The study's parts, run by the study driver (study_driver.hpp):
// load_surface_study() only reads (a simulated reference is run by
// run_surface()); the runs are a grid of the study core
// (study/model/study_model.hpp) with the rms_vs QoI, over the MPI farm with
// checkpoint and --resume; write_surface(), report_surface() and
// plot_surface() take the SurfaceResult.
//
// HDF5 result: /f (nf), /c_q (nc), /rms (nf x nc, m), /t_c (nf x nc, s),
// /status (nf x nc), /rhs_evaluations (nf x nc), /reference/t, /reference/z,
// /sweep/f, /sweep/t_c, /sweep/rhs_evaluations, /sweep/regression
// [intercept a (s), slope b (s), r^2]; attributes include the integrator that
// produced t_c, the number of MPI ranks (t_c is wall time per run) and, when
// every run misses the reference by more than its span, reference_warning. A
// kriged surface writes the grid's datasets only when the grid is run, and
// /gp and /surrogate (surface_kriging.hpp).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/metrics.hpp"
#include "io/hdf5_file.hpp"
#include "study/studies/study_driver.hpp"
#include "study/studies/study_spec.hpp"
#include "study/studies/surface_kriging.hpp"

namespace rover::study {

struct SurfaceStudy {
  std::string path, name, fingerprint;
  io::ScenarioSources sources;
  std::optional<IntegratorSettings> integrator;
  std::vector<double> f, c_q;        // the grid
  std::vector<double> sweep_f;       // the 1-D sweep (may be empty)
  double sweep_c_q = 0.14;
  // The reference: a curve read from a file (time offset applied), or the
  // run at (reference_f, reference_c_q) when simulate_reference.
  std::vector<double> reference_t, reference_z;
  bool simulate_reference = false;
  double reference_f = 0.0, reference_c_q = 0.0;
  std::string reference_description;
  // What a grid's rms values depend on besides (f, c_q): the scenario, rover
  // and terrain files and the reference with its offset (a fingerprint;
  // the root attribute runs_key of the result).
  std::string runs_key;
  SurfaceKrigingSpec kriging;        // enabled: the grid is predicted, not (only) run

  // The grid is run: no kriging, or kriging checked against the grid.
  bool runs_grid() const { return !kriging.enabled || kriging.check_grid; }
  // The files the study file names: its scenario, what that names, the reference file.
  io::InputFiles files;
};

SurfaceStudy load_surface_study(const std::string& path);

// A least-squares line t_c = intercept + slope f and its r^2.
struct LinearFit {
  double intercept = 0.0, slope = 0.0, r_squared = 0.0;
};

// The grid runs (nf x nc matrices, NaN where a run failed) and the sweep.
struct SurfaceResult {
  SurfaceStudy study;
  IntegratorSettings integrator;     // the one that produced t_c
  std::string scenario_name;
  Eigen::MatrixXd rms, t_c, rhs_evaluations;
  std::vector<int> status;           // [f index * nc + c_q index]
  std::vector<std::string> messages;
  std::vector<double> sweep_t_c, sweep_rhs_evaluations;  // [sweep point]
  LinearFit regression;              // of the sweep's successful runs
  int runs = 0, failed = 0;
  // The message of the failed run of the lowest task number (grid, sweep or
  // kriging design): why the study failed when every run did.
  std::string first_failure;
  int first_failure_task = -1;
  SurfaceKriging kriging;            // when study.kriging.enabled
  // Not empty when every run's RMS exceeds the span of the reference's
  // heights (core/reference_miss.hpp): a reference in millimetres, say.
  std::string reference_warning;
};

// Least squares y = a + b x (NaN for fewer than two points).
LinearFit linear_regression(const std::vector<double>& x, const std::vector<double>& y);

// Collective over MPI ranks; the result is meaningful on rank 0. Throws
// std::runtime_error if a simulated reference cannot be run.
SurfaceResult run_surface(const SurfaceStudy& study, const StudyRuntime& runtime);

void write_surface(const SurfaceResult& result, io::Hdf5Writer& h5);
// <results>_summary.png (the RMS error and t_c over f per c_q, the sweep);
// with PlotSelection::kAll also <results>_rms.png and <results>_tc.png (heat
// maps over (f, c_q)) and <results>_sweep.png (t_c over f with its
// regression).
void plot_surface(const SurfaceResult& result, const std::string& results_path, PlotSelection plots);
// The figures plot_surface writes with `plots`, one entry per file.
std::vector<PlannedFigure> surface_figures(const SurfaceStudy& study, PlotSelection plots);

// The study as the driver runs it.
StudyProgram<SurfaceResult> surface_program(SurfaceStudy study);

}  // namespace rover::study
