// Monte Carlo over the uncertain S-structure preloads (paper section 3.5,
// Fig. 13d): N samples of the 8 M0 ~ Normal(mean, sd) (MODEL.md section 5),
// one simulation each, and the 3-sigma confidence band of B_l z(t).
//
// Study file (configs/studies/preload_mc.json):
//   {"type": "montecarlo", "name": "preload_mc", "scenario": "../scenarios/drop_horizontal.json",
//    "samples": 1000, "seed": 20260101, "sd_scale": 1.0, "rest_time": 1.0,
//    "integrator": {...optional...}}
// sd_scale multiplies every standard deviation (0 collapses the band).
//
// HDF5 result: /samples/M0 (N x 8), /t, /curves/B_l_z (N x T, NaN where a run
// failed), /band/{mean,std,lower,upper,p00135,p99865} (T), /samples/deflection
// (z_r - z_min, m), /samples/at_rest (z_r, m), /samples/status (0 = ok),
// /samples/message, /samples/wall_time_s; attributes: seed, samples, sd_scale,
// integrator, scenario, fingerprint, project_version.
#pragma once

#include <string>

#include "study/study_config.hpp"

namespace rover::study {

struct MonteCarloStudy {
  StudyCommon common;
  int samples = 1000;
  std::uint64_t seed = 1;
  double sd_scale = 1.0;
  double rest_time_s = 1.0;
};

MonteCarloStudy load_montecarlo_study(const std::string& path);

struct StudyRunControl {
  std::string results_path;   // empty: results/<name>.h5
  bool resume = false;
  bool plot = true;
  int progress_interval_s = 5;
};

// Collective over MPI ranks; rank 0 writes the HDF5 file and the PNG.
// Returns the results path.
std::string run_montecarlo(const MonteCarloStudy& study, const StudyRunControl& control);

}  // namespace rover::study
