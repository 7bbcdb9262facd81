// The (f, c_q) surface predicted by kriging (docs/studies.md, "surface";
// Rasmussen & Williams 2006): a surface study with "surrogate": "gp" runs a
// Latin hypercube of N points over the grid's box instead of the grid (f
// log-uniform where its axis is log-spaced, c_q uniform), fits one Gaussian
// process (study/surrogate/gaussian_process.hpp) to each of the surface's
// QoIs, the RMS error and the computation time t_c, and predicts both on the
// grid with their predictive sd.
//
// The nugget is estimated by maximum likelihood: t_c is a wall time, its
// repeated runs differ, and an interpolating process (a fixed tiny nugget)
// is overconfident about it; on the RMS error the estimate falls to its lower
// bound and the process interpolates. The sd is that of a run at the point,
// sqrt(s^2(x) + tau sigma^2), the quantity the grid check compares. The
// noise of a wall time scales with the time (a loaded core slows a long run
// as much, relatively, as a short one), so t_c is kriged as log t_c: its
// map is exp(m) (the median), its sd is in log units (a relative sd), and its
// 3-sd band is [exp(m - 3 s), exp(m + 3 s)].
//
// The check, when the grid is also run ("check": "grid") or a surface result
// over the same grid is given ("check": {"file": ...}): per QoI and grid
// point the error of the prediction, and over the grid its Q^2, the largest
// error and the fraction of points within 3 predictive sd.
//
// Study file keys (beside those of surface.hpp):
//   "surrogate": "gp", "runs": 60 (>= 5), "seed": 7,
//   "check": "grid" | {"file": "results/f_cq_surface.h5"}   (optional),
//   "gp": {"trend": "constant" | "linear", "starts": 12}     (optional).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/hdf5_file.hpp"
#include "io/json_reader.hpp"
#include "study/estimators/design_matrix.hpp"
#include "study/surrogate/fitted_surrogate.hpp"

namespace rover::study {

inline constexpr int kMinSurfaceKrigingRuns = 5;
// A grid point lies within this many predictive sd of its prediction.
inline constexpr double kSurfaceCoverageSds = 3.0;

struct SurfaceKrigingSpec {
  bool enabled = false;
  int runs = 0;
  std::uint64_t seed = 1;
  bool check_grid = false;        // the grid is also run and compared
  std::string check_file;         // or a surface result over the same grid
  GaussianProcessSettings gp;     // the nugget estimated
  std::vector<Distribution> inputs;  // f, c_q over the grid's box
};

// Reads "surrogate", "runs", "seed", "check" and "gp" of a surface study
// (the axes' bounds and spacing given); errors name the file and field.
SurfaceKrigingSpec parse_surface_kriging(const io::JsonReader& r, const std::string& study_path, double f_min,
                                         double f_max, bool f_log, double c_q_min, double c_q_max, bool c_q_log);

// The design's points, runs x (f, c_q).
DesignMatrix surface_kriging_design(const SurfaceKrigingSpec& spec);

// One QoI over the grid: the prediction and, with a check, the errors.
struct SurfaceKrigingMap {
  std::string name;                // "rms", "t_c"
  bool log_scale = false;          // kriged as log(value): t_c
  bool wall_time = false;          // t_c: a measured cost, which scatters with the machine's load
  bool fitted = false;
  std::string undefined_reason;    // why there is no process
  FittedSurrogate model;           // of the value or, log_scale, of its log
  Eigen::MatrixXd mean, sd;        // nf x nc; log_scale: exp(m) and s in log units
  Eigen::MatrixXd lower, upper;    // the 3-sd band, in the value's units
  bool checked = false;
  Eigen::MatrixXd actual, error;   // nf x nc, NaN where the check's run failed
  double q2 = 0.0, max_abs_error = 0.0, coverage = 0.0;
  int checked_points = 0, covered_points = 0;
};

struct SurfaceKriging {
  DesignMatrix x;                  // the design, runs x (f, c_q)
  Eigen::VectorXd rms, t_c;        // per run, NaN where it failed
  std::vector<int> status;
  std::vector<std::string> messages;  // per run: why it failed, empty if it did not
  std::string check_source;        // "grid", the file, or empty
  std::vector<SurfaceKrigingMap> maps;  // rms, t_c
};

// Whether a map of the model's response (rms) is not to be trusted between
// its runs: its process interpolates them (no nugget) and predicts them, left
// out one at a time, with a Q2 below kDefaultQ2Threshold. A wall time's map
// (t_c) is never judged so: its runs scatter with the machine's load, and a
// process cannot predict noisy left-out runs whatever its mean map.
bool surface_map_not_to_trust(const SurfaceKrigingMap& m);

// Fits both QoIs on the successful runs of `k` and predicts them on the grid.
void fit_surface_kriging(const SurfaceKrigingSpec& spec, const std::vector<double>& f, const std::vector<double>& c_q,
                         SurfaceKriging& k);

// Compares the maps with grid values (nf x nc each, NaN where a run failed).
void check_surface_kriging(const Eigen::MatrixXd& rms, const Eigen::MatrixXd& t_c, const std::string& source,
                           SurfaceKriging& k);

// The grid values of a surface result file; throws io::ConfigError naming the
// file when it holds no /f, /c_q, /rms, /t_c, its grid differs from f, c_q, or
// its runs_key (SurfaceStudy::runs_key) differs from `runs_key`.
void read_surface_check(const std::string& path, const std::vector<double>& f, const std::vector<double>& c_q,
                        const std::string& runs_key, Eigen::MatrixXd& rms, Eigen::MatrixXd& t_c);

// /gp/design/{f, c_q, rms, t_c, status}, /gp/<qoi>/{mean, sd, lower, upper}
// (attribute log_scale) and, with a
// check, /gp/<qoi>/{actual, error} with attributes q2, max_abs_error,
// coverage_3sd; the processes under /surrogate (surrogate_file.hpp), so that
// `rover surrogate --predict` evaluates them (outputs "rms" and "log_t_c").
void write_surface_kriging(const SurfaceKriging& k, io::Hdf5Writer& h5);

void report_surface_kriging(const SurfaceKriging& k, std::ostream& out);

}  // namespace rover::study
