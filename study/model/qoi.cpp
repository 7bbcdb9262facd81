// See qoi.hpp.
#include "study/model/qoi.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/curve_overlap.hpp"
#include "core/name_list.hpp"
#include "core/metrics.hpp"
#include "core/number_text.hpp"
#include "core/run_note.hpp"
#include "io/checkpoint.hpp"

namespace rover::study {
namespace {

struct ChannelInfo {
  Channel channel;
  const char* name;
  const char* unit;
};
constexpr ChannelInfo kChannels[] = {
    {Channel::kBlz, "B_l_z", "m"},   {Channel::kBrz, "B_r_z", "m"},  {Channel::kGz, "G_z", "m"},
    {Channel::kPitch, "pitch", "rad"}, {Channel::kRoll, "roll", "rad"}, {Channel::kFn1, "Fn_1", "N"},
    {Channel::kFn2, "Fn_2", "N"},    {Channel::kFn3, "Fn_3", "N"},   {Channel::kFn4, "Fn_4", "N"}};

struct QoiInfo {
  QoiKind kind;
  const char* name;
  const char* unit;
  const char* description;
};
constexpr QoiInfo kQois[] = {
    {QoiKind::kBlzMin, "B_l_z_min", "m", "minimum of B_l z"},
    {QoiKind::kTMin, "t_min", "s", "time of the minimum of B_l z"},
    {QoiKind::kAtRest, "at_rest", "m", "B_l z at the end of the run"},
    {QoiKind::kDeflection, "deflection", "m", "B_l z at the end minus its minimum"},
    {QoiKind::kReboundPeak, "rebound_peak", "m", "maximum of B_l z after its minimum"},
    {QoiKind::kSettlingTime, "settling_time", "s",
     "last exit of B_l z from a band around its final value"},
    {QoiKind::kMaxAbsPitch, "max_abs_pitch", "rad", "maximum |pitch|"},
    {QoiKind::kMaxAbsRoll, "max_abs_roll", "rad", "maximum |roll|"},
    {QoiKind::kMaxWheelLoad, "max_wheel_load", "N", "largest normal force on any wheel"},
    {QoiKind::kBrRise, "B_r_rise", "m", "maximum rise of B_r z above its start"},
    {QoiKind::kGRise, "G_rise", "m", "maximum rise of G z above its start"},
    {QoiKind::kLateralDrift, "lateral_drift", "m", "y at the end minus y at the start"},
    {QoiKind::kYawDrift, "yaw_drift", "rad", "yaw at the end minus yaw at the start"},
    {QoiKind::kRmsVs, "rms_vs", "m", "RMS difference from a reference curve"}};

const QoiInfo& info(QoiKind kind) {
  for (const QoiInfo& q : kQois)
    if (q.kind == kind) return q;
  throw std::logic_error("unknown QoI kind");
}

const ChannelInfo& info(Channel channel) {
  for (const ChannelInfo& c : kChannels)
    if (c.channel == channel) return c;
  throw std::logic_error("unknown channel");
}

std::size_t argmin(const std::vector<double>& v) {
  return static_cast<std::size_t>(std::min_element(v.begin(), v.end()) - v.begin());
}

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

double max_rise(const std::vector<double>& v) {
  return *std::max_element(v.begin(), v.end()) - v.front();
}

double settling_time(const std::vector<double>& t, const std::vector<double>& z, double band) {
  const double final_value = z.back();
  for (std::size_t k = z.size(); k-- > 0;)
    if (std::abs(z[k] - final_value) > band) return k + 1 < t.size() ? t[k + 1] : t[k];
  return t.front();
}

double rms_against(const Trajectory& tr, const QoiSpec& spec) {
  const ReferenceCurve& ref = *spec.reference;
  std::vector<double> t_sim(tr.t.size());
  for (std::size_t k = 0; k < t_sim.size(); ++k) t_sim[k] = tr.t[k] + ref.time_offset_s;
  return rms_difference(t_sim, channel_values(tr, spec.channel), ref.t, ref.value);
}

}  // namespace

const std::vector<std::string>& channel_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const ChannelInfo& c : kChannels) n.emplace_back(c.name);
    return n;
  }();
  return names;
}

Channel channel_from_name(const std::string& name) {
  for (const ChannelInfo& c : kChannels)
    if (name == c.name) return c.channel;
  throw std::invalid_argument("unknown channel '" + name + "' (valid: " + comma_separated(channel_names()) + ")");
}

const char* channel_name(Channel channel) { return info(channel).name; }
const char* channel_unit(Channel channel) { return info(channel).unit; }

std::vector<double> channel_values(const Trajectory& tr, Channel channel) {
  switch (channel) {
    case Channel::kBlz: return tr.B_l_z;
    case Channel::kBrz: return tr.B_r_z;
    case Channel::kGz: return tr.G_z;
    case Channel::kPitch: return tr.pitch;
    case Channel::kRoll: return tr.roll;
    default: break;
  }
  const auto wheel = static_cast<Eigen::Index>(static_cast<int>(channel) - static_cast<int>(Channel::kFn1));
  std::vector<double> out(static_cast<std::size_t>(tr.normal_force_N.rows()));
  for (Eigen::Index k = 0; k < tr.normal_force_N.rows(); ++k)
    out[static_cast<std::size_t>(k)] = tr.normal_force_N(k, wheel);
  return out;
}

namespace {

bool is_impact_qoi(QoiKind kind) {
  switch (kind) {
    case QoiKind::kBlzMin: case QoiKind::kTMin: case QoiKind::kDeflection: case QoiKind::kReboundPeak:
    case QoiKind::kMaxWheelLoad: case QoiKind::kMaxAbsPitch: case QoiKind::kMaxAbsRoll:
      return true;
    default:
      return false;
  }
}

}  // namespace

std::string coarse_recording_warning(const std::vector<QoiSpec>& qois, double output_rate_hz) {
  if (!(output_rate_hz < kImpactQoiMinOutputRate_hz)) return "";
  std::vector<std::string> coarse;
  for (const QoiSpec& q : qois)
    if (is_impact_qoi(q.kind)) coarse.push_back(q.name);
  if (coarse.empty()) return "";
  return "the scenario records at output_rate " + number_text(output_rate_hz) + " Hz (a sample every " +
         number_text(1e3 / output_rate_hz) + " ms), and " + comma_separated(coarse) +
         " are read from those samples: an impact between them is missed; record at " +
         number_text(kImpactQoiMinOutputRate_hz) + " Hz or more (1000 Hz resolves the drops)";
}

const std::vector<std::string>& qoi_kind_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const QoiInfo& q : kQois) n.emplace_back(q.name);
    return n;
  }();
  return names;
}

QoiKind qoi_kind_from_name(const std::string& name) {
  for (const QoiInfo& q : kQois)
    if (name == q.name) return q.kind;
  throw std::invalid_argument("unknown quantity of interest '" + name + "' (valid: " +
                              comma_separated(qoi_kind_names()) + ")");
}

const char* qoi_unit(const QoiSpec& spec) {
  if (spec.kind == QoiKind::kRmsVs) return channel_unit(spec.channel);
  return info(spec.kind).unit;
}

std::string qoi_description(const QoiSpec& spec) {
  std::string d = info(spec.kind).description;
  if (spec.kind == QoiKind::kSettlingTime)
    d += " (band " + number_text(spec.settling_band) + " m)";
  if (spec.kind == QoiKind::kRmsVs && spec.reference)
    d += " " + spec.reference->path + " (channel " + channel_name(spec.channel) + ")";
  return d;
}

std::string qoi_definition(const QoiSpec& spec) {
  std::string d = info(spec.kind).name;
  if (spec.kind == QoiKind::kSettlingTime) d += ", band " + exact_number_text(spec.settling_band) + " m";
  if (spec.kind == QoiKind::kRmsVs && spec.reference) {
    std::string samples;
    for (std::size_t i = 0; i < spec.reference->t.size(); ++i)
      samples += exact_number_text(spec.reference->t[i]) + "," + exact_number_text(spec.reference->value[i]) + "\n";
    d += " of " + std::string(channel_name(spec.channel)) + " against a reference curve of " +
         std::to_string(spec.reference->t.size()) + " samples (digest " + io::config_fingerprint(samples) +
         "), time offset " + exact_number_text(spec.reference->time_offset_s) + " s";
  }
  return d;
}

double compute_qoi(const QoiSpec& spec, const Trajectory& tr) {
  if (tr.t.empty()) return std::nan("");
  const std::vector<double>& z = tr.B_l_z;
  switch (spec.kind) {
    case QoiKind::kBlzMin: return z[argmin(z)];
    case QoiKind::kTMin: return tr.t[argmin(z)];
    case QoiKind::kAtRest: return z.back();
    case QoiKind::kDeflection: return z.back() - z[argmin(z)];
    case QoiKind::kReboundPeak: {
      const std::size_t k = argmin(z);
      return *std::max_element(z.begin() + static_cast<std::ptrdiff_t>(k), z.end());
    }
    case QoiKind::kSettlingTime: return settling_time(tr.t, z, spec.settling_band);
    case QoiKind::kMaxAbsPitch: return max_abs(tr.pitch);
    case QoiKind::kMaxAbsRoll: return max_abs(tr.roll);
    case QoiKind::kMaxWheelLoad: return tr.normal_force_N.size() ? tr.normal_force_N.maxCoeff() : 0.0;
    case QoiKind::kBrRise: return max_rise(tr.B_r_z);
    case QoiKind::kGRise: return max_rise(tr.G_z);
    case QoiKind::kLateralDrift: return tr.q(tr.q.rows() - 1, coord::y) - tr.q(0, coord::y);
    case QoiKind::kYawDrift: return tr.q(tr.q.rows() - 1, coord::yaw) - tr.q(0, coord::yaw);
    case QoiKind::kRmsVs: return rms_against(tr, spec);
  }
  return std::nan("");
}

std::string reference_span_problem(const std::vector<double>& t, double offset_s, double duration_s) {
  if (t.empty()) return "";
  const double lo = offset_s, hi = offset_s + duration_s;
  constexpr double kTimeTolerance_s = 1e-12;  // as rms_difference
  const auto inside = static_cast<std::size_t>(std::count_if(
      t.begin(), t.end(), [&](double s) { return s >= lo - kTimeTolerance_s && s <= hi + kTimeTolerance_s; }));
  const std::string run = "spans " + number_text(t.front()) + " .. " + number_text(t.back()) + " s; the run's " +
                          number_text(duration_s) + " s with time_offset " + number_text(offset_s) +
                          " s cover reference times " + number_text(lo) + " .. " + number_text(hi) + " s";
  if (inside < kMinReferenceSamplesInRun)
    return run + ", which hold " + std::to_string(inside) + " of its samples, fewer than the " +
           std::to_string(kMinReferenceSamplesInRun) + " a comparison needs (times in seconds? the offset?)";
  if (const std::string p = curve_share_problem(t.front(), t.back(), lo, hi); !p.empty()) return run + ": " + p;
  return "";
}

std::string constant_reference_problem(const std::vector<double>& value) {
  if (value.empty()) return "";
  const auto [lo, hi] = std::minmax_element(value.begin(), value.end());
  if (*hi > *lo) return "";
  return "every one of its " + std::to_string(value.size()) + " heights is " + number_text(*lo) +
         " m: a constant curve has no motion to compare a run with (the wrong column?)";
}

bool settled_before_end(double settling_time_s, double duration_s) {
  return duration_s - settling_time_s >= kMinSettledShare * duration_s;
}

std::string qoi_note(const QoiSpec& spec, const Trajectory& tr) {
  const std::vector<double>& z = tr.B_l_z;
  if (z.size() < 2) return "";
  const double duration_s = tr.t.back() - tr.t.front();
  if (spec.kind == QoiKind::kAtRest &&
      !settled_before_end(settling_time(tr.t, z, QoiSpec{}.settling_band) - tr.t.front(), duration_s))
    return run_note(spec.name + " is no rest height",
                    "B_l z was still moving at the run's end (within " + number_text(QoiSpec{}.settling_band) +
                        " m of its last value for less than the last " + number_text(100.0 * kMinSettledShare) +
                        " % of the run), lengthen \"duration\"");
  if (spec.kind == QoiKind::kReboundPeak) {
    const auto peak = std::max_element(z.begin() + static_cast<std::ptrdiff_t>(argmin(z)), z.end());
    if (peak + 1 == z.end())
      return run_note(spec.name + " is the run's last sample",
                      "the rebound had not peaked by its end, lengthen \"duration\"");
  }
  return "";
}

}  // namespace rover::study
