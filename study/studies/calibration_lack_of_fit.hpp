// Whether the model describes calibration data at a point, whatever the
// method that found it (least squares or a posterior): each curve's residual
// lag-1 autocorrelation (study/estimators/residual_correlation.hpp), and for
// a noise sd the user gave, whether the residuals agree with it. Both
// methods assume independent Gaussian noise of that sd (docs/studies.md,
// "Calibration"); when the data say otherwise their intervals are too narrow
// (or, for a given noise sd far above the residuals' scatter, too wide).
#pragma once

#include <string>
#include <vector>

#include "study/studies/calibration.hpp"

namespace rover::study {

// Residuals contradict a given noise sd when chi2 = RSS / sd^2 lies in either
// tail of the chi-square law of n degrees of freedom (n points) beyond this
// probability: that of a normal variate more than 5 sd from its mean. The
// exact law, not n +- 5 sqrt(2n): for few points its tails are far from
// normal (the upper one heavier, the lower one never reaching n - 5 sqrt(2n)
// for n < 50).
inline constexpr double kNoiseContradictionTail = 2.866515718791939e-7;

// Empty, or why the residuals of some curves are correlated (`lag1`: per
// curve, NaN where its run failed): the model does not follow the data.
std::string residual_structure_reason(const CalibrationStudy& s, const std::vector<double>& lag1);

// Empty, or why `known_noise_sd_m` is contradicted by the residuals whose RSS
// per curve is `rss_m2` (NaN where the run failed): the residuals are far
// larger than the noise said, so intervals on that noise are too narrow, or
// far smaller, so they are too wide.
std::string noise_contradiction_reason(const CalibrationStudy& s, const std::vector<double>& rss_m2,
                                       double known_noise_sd_m);

struct LackOfFit {
  std::vector<double> residual_lag1;  // per curve; NaN where its run failed
  std::vector<double> residual_rms_m;  // per curve; NaN where its run failed
  std::string reason;                  // empty when the model describes the data
};

// Rank 0 (runs one simulation per curve): the residuals at `values` (the
// fitted parameters, in the order of CalibrationStudy::fit), judged as above;
// `known_noise_sd_m` <= 0 when the noise is not given.
LackOfFit lack_of_fit_at(const CalibrationStudy& s, const std::vector<double>& values, double known_noise_sd_m);

}  // namespace rover::study
