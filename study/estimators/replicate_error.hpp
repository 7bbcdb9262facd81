// The error of sampling estimates against the number of runs N, measured over
// independent replicates of a design: R independent randomisations (seeds) of
// Monte Carlo or of an Owen-scrambled Sobol' sequence, each estimate taken
// from a prefix of n = 2^k points (power-of-two prefixes of a Sobol' sequence
// are (t, m, s)-nets; Owen 1997), compared with a reference estimate. The
// replicates' spread is the reference-free error estimate of randomised
// quasi-Monte Carlo (L'Ecuyer and Lemieux 2002); their root-mean-square
// deviation from the reference adds the estimators' bias and the reference's
// own error.
//
// The error then follows a power law c N^p (p = -1/2 for Monte Carlo, Owen
// 1997: about -3/2 for scrambled nets on smooth integrands), fitted by least
// squares on (log N, log error), and the fit gives the number of runs for a
// target error.
//
// Pure functions of their arguments; they may run concurrently.
#pragma once

#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace rover::study {

// Sample mean and standard deviation (n - 1 denominator).
struct SampleMoments {
  double mean = std::numeric_limits<double>::quiet_NaN();
  double sd = std::numeric_limits<double>::quiet_NaN();
};

// Moments of values[0], ..., values[n - 1]. Throws std::invalid_argument if
// n < 2, n > values.size() or one of these values is not finite.
SampleMoments prefix_moments(std::span<const double> values, int n);

// Per column (time sample) of a family of curves, one curve per row: the mean
// and sd (n - 1) of rows 0 .. n - 1.
struct CurveMoments {
  Eigen::VectorXd mean, sd;
};

// Throws std::invalid_argument if n < 2, n > curves.rows() or a value in
// those rows is not finite (a failed run: a convergence measurement needs
// every run of a prefix, removing points would break a net's balance).
CurveMoments prefix_curve_moments(const Eigen::Ref<const Eigen::MatrixXd>& curves, int n);

// The powers of two 2^k with n_min <= 2^k <= n_max, increasing. Throws
// std::invalid_argument if n_min < 1 or there is none.
std::vector<int> power_of_two_sizes(int n_min, int n_max);

// R replicate estimates of one quantity (a scalar, or a curve on T samples)
// against a reference value of it.
struct ReplicateError {
  // sqrt( mean_r mean_t (estimate_r(t) - reference(t))^2 ): the RMS over the
  // replicates of the RMS (over t) deviation from the reference.
  double rms_error = std::numeric_limits<double>::quiet_NaN();
  // sqrt( mean_t var_r estimate_r(t) ), var with R - 1: the RMS error of one
  // replicate about the replicates' mean, without the reference.
  double spread = std::numeric_limits<double>::quiet_NaN();
};

// `estimates`: R x T, one replicate per row; `reference`: T values. Throws
// std::invalid_argument if R < 2, T < 1, the sizes differ or a value is not
// finite.
ReplicateError replicate_error(const Eigen::Ref<const Eigen::MatrixXd>& estimates,
                               const Eigen::Ref<const Eigen::VectorXd>& reference);
// The scalar case (T = 1).
ReplicateError replicate_error(std::span<const double> estimates, double reference);

// error(N) = coefficient * N^exponent, fitted by ordinary least squares of
// log(error) on log(N).
struct PowerLawFit {
  double exponent = std::numeric_limits<double>::quiet_NaN();
  double coefficient = std::numeric_limits<double>::quiet_NaN();
  // Standard error of the exponent from the residuals (NaN with two points).
  double exponent_se = std::numeric_limits<double>::quiet_NaN();
  int points = 0;
  double n_min = std::numeric_limits<double>::quiet_NaN();  // the fitted range of N
  double n_max = std::numeric_limits<double>::quiet_NaN();

  double error_at(double n) const;  // coefficient * n^exponent
};

// Throws std::invalid_argument if the spans differ in size, there are fewer
// than two points, an N or an error is not finite and positive, or all N are
// equal.
PowerLawFit fit_power_law(std::span<const double> n, std::span<const double> error);

// The number of runs needed for an error of `target` (> 0).
struct RunsForError {
  // From the fit: (target / coefficient)^(1 / exponent); +inf when the fitted
  // error does not decrease (exponent >= 0).
  double fitted = std::numeric_limits<double>::quiet_NaN();
  // The smallest measured N from which the measured error stays <= target
  // (at that N and at every larger one); 0 if the largest N's error is above.
  int observed = 0;
  // `fitted` lies outside the fitted range [n_min, n_max] of N.
  bool extrapolated = true;
};

// `sizes` increasing, errors[k] measured at sizes[k]. Throws
// std::invalid_argument if target <= 0, the spans differ in size or are empty,
// or the sizes do not increase.
RunsForError runs_for_error(const PowerLawFit& fit, std::span<const int> sizes,
                            std::span<const double> errors, double target);

}  // namespace rover::study
