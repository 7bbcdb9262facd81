// See curve_overlap.hpp.
#include "core/curve_overlap.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/number_text.hpp"

namespace rover {
namespace {

std::string percent_text(double share) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g %%", 100.0 * share);
  return text;
}

}  // namespace

double span_share_within(double t_first, double t_last, double lo, double hi) {
  if (!(t_last > t_first)) return t_first >= lo && t_first <= hi ? 1.0 : 0.0;
  return std::max(0.0, std::min(hi, t_last) - std::max(lo, t_first)) / (t_last - t_first);
}

std::string curve_share_problem(double t_first, double t_last, double lo, double hi) {
  const double share = span_share_within(t_first, t_last, lo, hi);
  if (share >= kMinCurveShareCompared) return "";
  return "only " + percent_text(share) + " of its time span (t " + number_text(t_first) + " .. " +
         number_text(t_last) + ") lies within them, less than the " + percent_text(kMinCurveShareCompared) +
         " a comparison needs: t runs to " + number_text(t_last) +
         ", milliseconds? (a longer record: cut it to the times compared)";
}

std::string milliseconds_hint(double t_last, double span_end_s) {
  if (!(span_end_s > 0.0) || !(t_last * kMinCurveShareCompared > span_end_s)) return "";
  return ": t runs to " + number_text(t_last) + ", milliseconds?";
}

double sample_time_tolerance_s(const std::vector<double>& t_a, const std::vector<double>& t_b) {
  const auto mean_step = [](const std::vector<double>& t) {
    return (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  };
  return kSampleTimeToleranceShare * std::min(mean_step(t_a), mean_step(t_b));
}

CommonSpan common_span(const std::vector<double>& t_a, const std::vector<double>& t_b) {
  return {std::max(t_a.front(), t_b.front()), std::min(t_a.back(), t_b.back())};
}

std::optional<double> time_in_span(double t_s, const CommonSpan& span, double tolerance_s) {
  if (!(t_s >= span.first_s - tolerance_s && t_s <= span.last_s + tolerance_s)) return std::nullopt;
  return std::clamp(t_s, span.first_s, span.last_s);
}

}  // namespace rover
