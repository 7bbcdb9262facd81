// See reference_miss.hpp.
#include "core/reference_miss.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/number_text.hpp"

namespace rover {

double value_span(const std::vector<double>& values) {
  double low = std::numeric_limits<double>::infinity();
  double high = -low;
  for (const double v : values) {
    if (!std::isfinite(v)) continue;
    low = std::min(low, v);
    high = std::max(high, v);
  }
  return high >= low ? high - low : 0.0;
}

bool every_rms_exceeds_span(const std::vector<double>& rms, double span) {
  bool any_finite = false;
  for (const double v : rms) {
    if (!std::isfinite(v)) continue;
    if (!(v > span)) return false;
    any_finite = true;
  }
  return any_finite;
}

std::string reference_missed_text(const std::string& who, const std::string& reference, double span,
                                  const std::string& unit, const std::string& what) {
  return who + " the reference " + reference + " by more than the " + number_text(span) +
         (unit.empty() ? "" : " " + unit) +
         " its values span: are they in SI units (metres, not millimetres), and of the " + what + "?";
}

}  // namespace rover
