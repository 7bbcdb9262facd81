// Trajectory files: HDF5 (datasets /t, /B_l_z, /B_r_z, /G_z, /pitch, /roll,
// /q (T x 23), /u (T x 23), /Fn (T x 4), with attributes recording every
// parameter, the integrator and its settings, wall time, right-hand-side
// evaluations, the project version, and the quality of the friction gammas
// used: friction_fit_rms, friction_fit_peak_mu, friction_fit_acceptable 0/1),
// the same columns as CSV, and PNG plots (paper Fig. 11). Also reading a curve
// back for `rover compare` and calibration data.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "core/simulate.hpp"
#include "io/scenario_config.hpp"

namespace rover::io {

// Both written atomically (temporary file + rename). `stop` (if given) is
// read between the datasets and before the commit (HDF5), every
// kStopCheckRows rows (CSV, see write_csv): once it is set, the temporary is
// removed, nothing is written at `path` (an earlier file there stays) and
// false is returned; true when the file was written.
bool write_trajectory_hdf5(const std::string& path, const Trajectory& trajectory,
                           const ScenarioSetup& setup, const ModelInputs& inputs,
                           const std::atomic<bool>* stop = nullptr);
bool write_trajectory_csv(const std::string& path, const Trajectory& trajectory,
                          const std::atomic<bool>* stop = nullptr);

// Drop tests: B_l z(t) (Fig. 11a-b). Obstacle runs: B_l, B_r, G z(t) and a
// second file with pitch and roll (Fig. 11c-h). Returns the files written:
// once `stop` (if given) is set, no further plot is begun.
std::vector<std::string> write_trajectory_plots(const std::string& png_stem,
                                                const Trajectory& trajectory,
                                                const std::string& title, bool obstacle_run,
                                                const std::atomic<bool>* stop = nullptr);

// A named curve (t, y) from a trajectory file: HDF5 (/t and /<column>) or CSV
// with a header (column "t" and the named one, or "z" for measured drop data,
// read by read_measured_curve with its bound on |z|; a "z" whose header
// declares another channel than `column` is refused, see declared_channel).
// Times must increase
// strictly over at least 3 samples and every value be finite; throws
// ConfigError naming the file and the line (CSV) or the sample (HDF5). The
// HDF5 record of a failed run (attribute status_code not 0) is refused with
// the run's recorded status and message.
struct Curve {
  std::vector<double> t, y;
};
Curve read_curve(const std::string& path, const std::string& column = "B_l_z");

}  // namespace rover::io
