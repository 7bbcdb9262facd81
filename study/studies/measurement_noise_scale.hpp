// The measurement noise sds a Gaussian likelihood can use (docs/configuration.md):
// heights are below 1e3 m (io::kMeasuredCurveMaxAbsHeight_m), and below
// 1e-12 m the noise is under the rounding of the data's digits; far outside
// these bounds the likelihood's residual^2 / sd^2 is not a finite number.
// Shared by mcmc.noise_sd and the next-experiment candidates' noise_sd.
#pragma once

#include <string>

#include "study/studies/report_number.hpp"

namespace rover::study {

constexpr double kMinNoiseSd_m = 1e-12;
constexpr double kMaxNoiseSd_m = 1e3;

inline bool noise_sd_resolved(double sd_m) { return sd_m >= kMinNoiseSd_m && sd_m <= kMaxNoiseSd_m; }

// "<sd> m, outside the noise sds from 1e-12 to 1000 m that ...": the reason a
// noise sd is refused.
inline std::string noise_scale_problem(double sd_m) {
  return format_number(sd_m, 6) + " m, outside the noise sds from " + format_number(kMinNoiseSd_m, 6) + " to " +
         format_number(kMaxNoiseSd_m, 6) + " m that the likelihood resolves (heights are in metres)";
}

}  // namespace rover::study
