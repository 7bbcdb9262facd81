// How much of a curve lies within the times it is compared over: a run's
// span, or the common interval of two curves (docs/reliability.md, "Numbers
// beyond the model's scale"). A curve whose times are in milliseconds beside
// a run in seconds shares about a thousandth of its span with it (a 0.3 s
// drop recorded at 20 kHz in milliseconds: 7 of its 6000 samples, its first
// 0.3 ms), enough samples for an RMS that says nothing. One rule and one
// sentence for every reader of such a curve: `rover compare`, a study's
// reference curves (qoi[i].reference, a surface's reference.file) and the
// hint of a calibration's data that run past the simulated end.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace rover {

// At least this share of a compared curve's time span must lie within the
// times compared: a record 50 times longer than the run passes; a curve in
// milliseconds fails unless the run is 20 times longer than the record.
inline constexpr double kMinCurveShareCompared = 0.02;

// The share of [t_first, t_last] that lies within [lo, hi]; for a curve of
// one instant, 1 if it lies there, else 0.
double span_share_within(double t_first, double t_last, double lo, double hi);

// Empty if at least kMinCurveShareCompared of [t_first, t_last] lies within
// [lo, hi]; otherwise "only 0.1 % of its time span (t 0 .. 300) lies within
// them, less than the 2 % a comparison needs: t runs to 300, milliseconds?
// (a longer record: cut it to the times compared)".
std::string curve_share_problem(double t_first, double t_last, double lo, double hi);

// ": t runs to 300, milliseconds?" when a curve that ends at t_last runs on
// beyond a span ending at span_end_s by more than the share rule allows
// (t_last above span_end_s / kMinCurveShareCompared), else "".
std::string milliseconds_hint(double t_last, double span_end_s);

// Two curves' times on one clock agree to rounding (0.28 s and
// 0.27999999999999997 s after an offset is subtracted) within this share of
// the finer curve's mean sampling step.
inline constexpr double kSampleTimeToleranceShare = 1e-3;

// kSampleTimeToleranceShare of the finer of the two curves' mean sampling
// steps (each at least two increasing times).
double sample_time_tolerance_s(const std::vector<double>& t_a, const std::vector<double>& t_b);

// The times both curves cover, [max of the firsts, min of the lasts].
struct CommonSpan {
  double first_s = 0.0, last_s = 0.0;
};
CommonSpan common_span(const std::vector<double>& t_a, const std::vector<double>& t_b);

// `t_s` within the common span, to `tolerance_s`, as a time of the span (a
// time a rounding beyond an end is that end); nullopt if it lies farther out.
std::optional<double> time_in_span(double t_s, const CommonSpan& span, double tolerance_s);

}  // namespace rover
