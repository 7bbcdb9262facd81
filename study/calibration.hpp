// Calibration against a measured drop curve: NLopt minimises the RMS between
// the simulated and the measured B_l z over chosen parameters within bounds.
//
// Parameters that can be fitted: "c_q" [N m s/rad], "f" [1/rad] (searched in
// log10), "M0_scale" (multiplies all eight preloads), "time_offset" [s]. The
// measured curve's time origin need not be the release: data time t_d maps to
// simulation time t_d - time_offset. Unless time_offset is fitted by NLopt it
// is profiled out: for every simulated curve the best offset in
// "time_offset_range" is found by a 1 ms scan and a golden-section polish
// (cheap: no new simulation). Before the release the simulated curve is held
// at its initial value, after the end at its final value.
//
// Study file (configs/studies/calibration.json):
//   {"type": "calibration", "name": "calibration", "scenario": "../scenarios/drop_horizontal.json",
//    "data": "../data/drop_horizontal_synthetic.csv",
//    "fit": ["c_q"], "algorithm": "LN_BOBYQA", "max_evaluations": 40, "xtol_rel": 1e-3,
//    "bounds": {"c_q": [0.02, 1.0], "f": [1e2, 1e5], "M0_scale": [0.8, 1.2], "time_offset": [-0.2, 0.2]},
//    "initial": {"c_q": 0.1, "f": 1e4, "M0_scale": 1.0, "time_offset": 0.0},
//    "starts": 1, "seed": 1}
// "starts" > 1 runs that many local searches (start 0 from "initial", the
// others from seeded random points in the bounds), fanned out over MPI ranks.
//
// Measured data: CSV with the header t,z (s, metres of the left bogie pin B_l);
// '#' comment lines allowed; a malformed line is reported with its number.
//
// HDF5 result: /history (E x (p + 3): the p parameters, time_offset, rms,
// status, one row per evaluation in order), /history_start (E), /best/values
// (p), /best/names, /best/time_offset, /best/rms, /data/t, /data/z, /fit/t,
// /fit/z (the best curve in data time); attributes algorithm, parameter names.
#pragma once

#include <string>
#include <vector>

#include "study/montecarlo.hpp"
#include "study/study_config.hpp"

namespace rover::study {

struct FitParameter {
  std::string name;
  double lower = 0.0, upper = 0.0, initial = 0.0;
  bool log_scale = false;
};

struct CalibrationStudy {
  StudyCommon common;
  std::string data_path;
  std::vector<double> data_t, data_z;
  std::vector<FitParameter> fit;
  std::string algorithm = "LN_BOBYQA";
  int max_evaluations = 40;
  double xtol_rel = 1e-3;
  double offset_min_s = -0.2, offset_max_s = 0.2, offset_initial_s = 0.0;
  int starts = 1;
  std::uint64_t seed = 1;
};

struct CalibrationOverrides {
  std::string data_path;                 // empty: the study's
  std::vector<std::string> fit;          // empty: the study's
  std::string algorithm;                 // empty: the study's
  int starts = 0, max_evaluations = 0;   // 0: the study's
};

CalibrationStudy load_calibration_study(const std::string& path, const CalibrationOverrides& overrides = {});

// RMS between measured (t_d, z_d) and a simulated curve (t, z) shifted by
// offset: z(t_d - offset), held constant outside the simulated interval.
double shifted_rms(const std::vector<double>& t, const std::vector<double>& z,
                   const std::vector<double>& t_d, const std::vector<double>& z_d, double offset);

// The offset in [lo, hi] minimising shifted_rms (scan + golden section).
double best_offset(const std::vector<double>& t, const std::vector<double>& z,
                   const std::vector<double>& t_d, const std::vector<double>& z_d, double lo,
                   double hi);

std::string run_calibration(const CalibrationStudy& study, const StudyRunControl& control);

}  // namespace rover::study
