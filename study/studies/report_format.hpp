// How the studies show their results on the console and in figures: lengths
// in mm and everything else in the unit it is stored in (SI,
// docs/results_format.md), numbers with a fixed number of decimals, and
// Eigen vectors as the plain vectors plots and result files take.
#pragma once

#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rover::study {

struct DisplayUnit {
  double factor = 1.0;  // shown value = factor * stored value
  std::string name;     // "mm" for a stored "m"
};

inline DisplayUnit display_unit(const std::string& stored_unit) {
  constexpr double kMillimetresPerMetre = 1000.0;
  if (stored_unit == "m") return {kMillimetresPerMetre, "mm"};
  return {1.0, stored_unit};
}

// x with `digits` decimals: fixed_text(0.12345) == "0.123".
inline std::string fixed_text(double x, int digits = 3) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << x;
  return os.str();
}

inline std::vector<double> to_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace rover::study
