// How the studies show their results on the console and in figures: lengths
// in mm and everything else in the unit it is stored in (SI,
// docs/results_format.md), numbers with a fixed number of decimals, and
// Eigen vectors as the plain vectors plots and result files take.
#pragma once

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rover::study {

// Width of the input names in the console tables of indices and effects.
inline constexpr int kIndexLabelWidth = 28;
// Inputs whose aggregated total Sobol' index exceeds this are drawn along time.
inline constexpr double kPlottedTotalIndex = 0.01;

struct DisplayUnit {
  double factor = 1.0;  // shown value = factor * stored value
  std::string name;     // "mm" for a stored "m"
};

inline DisplayUnit display_unit(const std::string& stored_unit) {
  constexpr double kMillimetresPerMetre = 1000.0;
  if (stored_unit == "m") return {kMillimetresPerMetre, "mm"};
  return {1.0, stored_unit};
}

// x with `digits` decimals: fixed_text(0.12345) == "0.123". A value of a
// million or more (or not finite) in "%.6g" form: 1e+308 as "1e+308", not
// as 309 digits.
inline std::string fixed_text(double x, int digits = 3) {
  constexpr double kLargestFixed = 1e6;
  if (!(std::abs(x) < kLargestFixed)) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", x);
    return text;
  }
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << x;
  return os.str();
}

// A confidence level as a percentage with the digits it has: 0.95 -> "95",
// 0.999999 -> "99.9999" (never rounded to a level it is not).
inline std::string percent_digits(double confidence) {
  std::ostringstream os;
  os << std::setprecision(10) << 100.0 * confidence;
  return os.str();
}

// Lengths stored in metres, as shown: in millimetres.
inline std::vector<double> in_millimetres(const std::vector<double>& metres) {
  const double factor = display_unit("m").factor;
  std::vector<double> shown;
  shown.reserve(metres.size());
  for (double length : metres) shown.push_back(factor * length);
  return shown;
}

inline std::vector<double> to_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace rover::study
