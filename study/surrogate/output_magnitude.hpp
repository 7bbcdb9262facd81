// The largest output a surrogate fits. Variances, least-squares sums and the
// Gaussian process's likelihood square the outputs; beyond
// kMaxSurrogateOutput those squares overflow a double and a fit would report
// an infinite mean or variance instead of failing.
#pragma once

#include <cmath>
#include <string>

#include <Eigen/Core>

#include "core/number_text.hpp"

namespace rover::study {

inline constexpr double kMaxSurrogateOutput = 1e150;

// "" or why output `name` cannot be fitted: its first value beyond the bound.
inline std::string output_magnitude_problem(const Eigen::VectorXd& y, const std::string& name) {
  for (Eigen::Index r = 0; r < y.size(); ++r)
    if (std::abs(y(r)) > kMaxSurrogateOutput)
      return "output '" + name + "' is " + number_text(y(r)) + " at run " + std::to_string(r) + ", beyond +-" +
             number_text(kMaxSurrogateOutput) + ", where its square overflows a double: rescale it (a unit mistake?)";
  return "";
}

}  // namespace rover::study
