// Confidence bands of a family of curves sampled on one time grid (paper
// Fig. 13d): per time sample, mean, standard deviation, mean -+ 3 sd, and the
// empirical 0.135 % and 99.865 % quantiles (the 3-sigma levels of a normal).
#pragma once

#include <vector>

#include <Eigen/Core>

namespace rover::study {

struct Band {
  std::vector<double> mean, std, lower, upper, p00135, p99865;
  int samples_used = 0;  // rows without NaN
};

// `curves`: one row per sample, one column per time; rows with any NaN (failed
// runs) are left out. sd is the sample standard deviation (n - 1).
Band band_statistics(const Eigen::MatrixXd& curves);

// Empirical quantile with linear interpolation between order statistics
// (Hyndman-Fan type 7, numpy's default). `sorted` must be sorted.
double quantile(const std::vector<double>& sorted, double p);

}  // namespace rover::study
