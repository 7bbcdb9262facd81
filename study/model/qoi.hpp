// Quantities of interest (QoIs): named scalars computed from one simulated
// trajectory (docs/model.md §8 gives its outputs), and output channels (curves
// on the output time grid). One piece of code shared by every study.
//
// With z = B_l z(t) (the world height of the left bogie pin) on t_0 .. t_end:
//   B_l_z_min      [m]   min_t z
//   t_min          [s]   the first time z reaches that minimum
//   at_rest        [m]   z(t_end)
//   deflection     [m]   z(t_end) - min_t z           (numerator of paper eq. 10)
//   rebound_peak   [m]   max of z over t > t_min       (the rebound after the compression)
//   settling_time  [s]   the last time z is outside [z(t_end) - band, z(t_end) + band]
//                        (t_0 if never; band default 0.5 mm, "band" in the spec); a run
//                        that stayed in the band for less than 5 % of it has not settled
//                        (settled_before_end): the studies warn, evaluate marks the row
//   max_abs_pitch  [rad] max_t |chi|, max_abs_roll [rad] max_t |psi|
//   max_wheel_load [N]   max over t and the four wheels of the total normal force
//   B_r_rise       [m]   max_t B_r z - B_r z(t_0); G_rise [m] likewise for the chassis CoM G
//   lateral_drift  [m]   y(t_end) - y(t_0);   yaw_drift [rad] theta(t_end) - theta(t_0)
//   rms_vs         [m]   RMS of (channel - reference) over the common interval, the reference
//                        (a measured t,z CSV or an HDF5 trajectory) shifted by its time offset
//                        and interpolated linearly (docs/model.md §8)
// Channels: B_l_z, B_r_z, G_z [m], pitch, roll [rad], Fn_1 .. Fn_4 [N].
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/simulate.hpp"

namespace rover::study {

enum class Channel { kBlz, kBrz, kGz, kPitch, kRoll, kFn1, kFn2, kFn3, kFn4 };
const std::vector<std::string>& channel_names();
Channel channel_from_name(const std::string& name);  // throws std::invalid_argument listing them
const char* channel_name(Channel channel);
const char* channel_unit(Channel channel);
std::vector<double> channel_values(const Trajectory& trajectory, Channel channel);

enum class QoiKind {
  kBlzMin, kTMin, kAtRest, kDeflection, kReboundPeak, kSettlingTime, kMaxAbsPitch, kMaxAbsRoll,
  kMaxWheelLoad, kBrRise, kGRise, kLateralDrift, kYawDrift, kRmsVs
};

// A measured or reference curve for rms_vs, on its own clock.
struct ReferenceCurve {
  std::string path;
  std::vector<double> t, value;
  double time_offset_s = 0.0;  // reference time = simulation time + offset
};

struct QoiSpec {
  std::string name;           // as written in the study (unique within it)
  QoiKind kind = QoiKind::kBlzMin;
  double settling_band = 5e-4;                      // settling_time [channel units]
  Channel channel = Channel::kBlz;                  // rms_vs
  std::shared_ptr<const ReferenceCurve> reference;  // rms_vs
};

// QoIs of an impact (an extreme or its time) are read from the recorded
// samples: below this output rate the samples step over the drops' impacts,
// which last a few milliseconds (at 20 Hz B_l_z_min comes out 2 mm high; at
// 100 Hz within 0.05 mm of the value at 1 kHz).
inline constexpr double kImpactQoiMinOutputRate_hz = 100.0;

// Empty, or a warning naming the impact QoIs of `qois` when a run recorded at
// `output_rate_hz` is too coarse for them (kImpactQoiMinOutputRate_hz).
std::string coarse_recording_warning(const std::vector<QoiSpec>& qois, double output_rate_hz);

const std::vector<std::string>& qoi_kind_names();
QoiKind qoi_kind_from_name(const std::string& name);  // throws std::invalid_argument listing them
const char* qoi_unit(const QoiSpec& spec);
std::string qoi_description(const QoiSpec& spec);
// What a QoI's values are, exactly enough to tell two files' values of one
// name apart: its kind, and the settling band, or the channel, reference
// curve (its samples, digested) and time offset of rms_vs. Written with the
// values, as the attribute kQoiDefinitionAttribute of /qoi/<name>.
std::string qoi_definition(const QoiSpec& spec);
inline constexpr const char* kQoiDefinitionAttribute = "definition";

// The fewest samples of a reference curve inside the span of a run: fewer
// and the RMS compares the run with a line between two points.
inline constexpr std::size_t kMinReferenceSamplesInRun = 3;

// Why a reference curve (times `t`, reference time = simulation time +
// offset_s) cannot be compared with a run of duration_s: the run covers
// reference times [offset_s, offset_s + duration_s], and fewer than
// kMinReferenceSamplesInRun of its samples lie there (a curve in
// milliseconds, an offset beyond the curve, a run far shorter than the
// record), or less than kMinCurveShareCompared of its time span
// (core/curve_overlap.hpp: a curve in milliseconds recorded at 20 kHz).
// Empty if it can. Names both spans and the offset.
std::string reference_span_problem(const std::vector<double>& t, double offset_s, double duration_s);

// Why a reference of heights says nothing about a run: every value is the
// same (a wrong column, a placeholder). Empty if the values vary.
std::string constant_reference_problem(const std::vector<double>& value);

// The QoI of a trajectory with at least one sample. A trajectory that ended
// early (failed run) still has values, but studies do not use them.
double compute_qoi(const QoiSpec& spec, const Trajectory& trajectory);

// A settling time counts as one when z then stayed within its band for at
// least kMinSettledShare of the run: a curve still moving at the end leaves
// the band around its last value just before the end (or at it), and that
// time says nothing about settling.
inline constexpr double kMinSettledShare = 0.05;
// A settling band wider than this is a unit mistake: the drop's whole
// travel is a few centimetres.
inline constexpr double kMaxSettlingBand_m = 0.05;
bool settled_before_end(double settling_time_s, double duration_s);

// Empty, or why the QoI's value of this trajectory is not what its name says:
// at_rest of a run whose B_l z had not settled at its end (by the default
// settling band, settled_before_end), rebound_peak of a run whose highest
// point after the compression is its last sample (the rebound had not
// peaked). The studies report such notes with the run.
std::string qoi_note(const QoiSpec& spec, const Trajectory& trajectory);

}  // namespace rover::study
