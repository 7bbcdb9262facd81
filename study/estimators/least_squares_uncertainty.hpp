// Uncertainty of a least-squares fit at its optimum (Bates & Watts 1988,
// "Nonlinear Regression Analysis and Its Applications", section 2.3).
//
// Linear approximation: with J the n x p Jacobian of the residuals and
// s^2 = RSS / (n - rank J), the covariance of the estimate is s^2 (J^T J)^-1
// and each parameter's interval is x_j -+ t_{n-rank}((1+confidence)/2) se_j.
// (J^T J)^-1 is never formed: J's columns are scaled to unit norm and
// J D^-1 = U S V^T is taken by SVD (Golub & Van Loan 2013, section 5.5), so
// cov = s^2 D^-1 V S^-2 V^T D^-1. Singular values below
// max(n, p) eps sigma_max count as zero (the rank). A parameter with a
// component in the null space of J is not identifiable: its standard error is
// +inf, its interval (-inf, inf) and its covariance row NaN (diagonal +inf);
// the identifiable parameters keep the pseudo-inverse covariance, which is
// exact for them.
//
// Profile likelihood (Bates & Watts 1988, ch. 6; Venzon & Moolgavkar 1988):
// with the noise variance s^2 taken as known, the parameter values where
// (RSS_profile - RSS_min) / s^2 <= chi2_1(confidence).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

namespace rover::study {

struct LeastSquaresUncertainty {
  double noise_sd = 0;            // s
  int degrees_of_freedom = 0;     // n - rank (= n - p when J has full rank)
  Eigen::MatrixXd covariance, correlation;
  Eigen::VectorXd standard_error, lower, upper;
  int rank = 0;                   // of J; < p means some parameter combination is not identifiable
  double condition_number = 0;    // of the column-scaled J (sigma_max / sigma_min); inf if rank < p
  std::string warning;            // empty when J has full rank and is well conditioned
};

// parameters: the optimum x (p); residuals at x (n > p); jacobian d residual /
// d x (n x p); names: empty or p names used in the warning. Throws
// std::invalid_argument on mismatched sizes, non-finite input, n <= p or a
// confidence outside (0, 1).
LeastSquaresUncertainty gauss_newton_uncertainty(const Eigen::VectorXd& parameters,
                                                 const Eigen::VectorXd& residuals,
                                                 const Eigen::MatrixXd& jacobian,  // n x p
                                                 double confidence = 0.95,
                                                 const std::vector<std::string>& names = {});

// How to difference f along one parameter.
enum class DifferenceScheme {
  central,   // (f(x + h) - f(x - h)) / 2h, both points inside the bounds
  one_sided  // (f(x + h) - f(x)) / h, h signed to point into the bounds
};
struct DifferenceStep {
  double step = 0;  // h
  DifferenceScheme scheme = DifferenceScheme::central;
};

// Per parameter: nominal h_j = cbrt(eps) * max(|x_j|, typical_j) (the step
// balancing the O(h^2) truncation and O(eps/h) rounding error of a central
// difference), reduced so x_j -+ h_j stay inside [lower_j, upper_j]. Reducing
// h by r multiplies the rounding error by r; once the room to the nearer bound
// is below sqrt(eps) * max(|x_j|, typical_j) (r ~ eps^(-1/6) ~ 400) a
// one-sided difference with that optimal forward step is more accurate, so it
// is used, pointing to the side with more room (and clipped to it).
// typical_j > 0 is the parameter's scale; requires lower_j <= x_j <= upper_j,
// lower_j < upper_j.
std::vector<DifferenceStep> finite_difference_steps(const Eigen::VectorXd& x,
                                                    const Eigen::VectorXd& lower,
                                                    const Eigen::VectorXd& upper,
                                                    const Eigen::VectorXd& typical);

// The steps of finite_difference_steps as numbers: a central step is > 0 and
// x_j -+ h_j are both inside the bounds; where x_j is too close to a bound for
// a central difference the one-sided step is returned, signed into the bounds
// (then only x_j + h_j is inside; (f(x + h) - f(x)) / h works for either sign).
Eigen::VectorXd central_difference_steps(const Eigen::VectorXd& x, const Eigen::VectorXd& lower,
                                         const Eigen::VectorXd& upper, const Eigen::VectorXd& typical);

// Profile-likelihood interval of one parameter. values: strictly ascending
// grid; rss: minimised residual sum of squares with the parameter fixed at
// each value (finite); noise_variance: s^2 > 0. The best value is the grid
// minimum, refined by the vertex of the parabola through it and its two
// neighbours when it is interior (exact for a quadratic profile); the interval
// is the connected set around it where (rss - rss_min) / s^2 <= chi2_1(confidence),
// ends interpolated linearly between grid points. An end where the profile
// never rises above the threshold before the grid ends is open (+-inf) and
// flagged; when both ends are open the parameter is not identifiable from
// these data.
struct ProfileInterval {
  double best = 0, lower = 0, upper = 0;
  bool lower_open = false, upper_open = false, identifiable = true;
};
ProfileInterval profile_likelihood_interval(const std::vector<double>& values,
                                            const std::vector<double>& rss, double noise_variance,
                                            double confidence = 0.95);

}  // namespace rover::study
