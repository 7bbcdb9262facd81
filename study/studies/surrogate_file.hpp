// A fitted surrogate set on disk: what `rover surrogate --study` saves and
// `rover surrogate --predict` reads back, one model per QoI over the same
// inputs. The layout (docs/results_format.md, "surrogate"):
//
//   /surrogate               attributes kind ("pce" | "gp"), q2_threshold
//   /surrogate/inputs/{names, labels, distribution (d strings), parameters
//       (d x 4: a, b, lower, upper of study::Distribution), support (d x 2)}
//   /surrogate/outputs       the QoI names, in order
//   /surrogate/models/<qoi>  group attributes q2_loo, test_points, q2_test,
//                            rmse_test, warning, runs
//     pce: multi_indices (terms x d), coefficients (terms); attributes degree,
//          q_norm, candidate_terms, constant_output
//     gp:  input_offset, input_scale, length_scales (d), scaled_inputs (n x d),
//          trend_coefficients, weights, loo_mean, loo_variance,
//          correlation_cholesky (n x n), trend_cholesky, whitened_trend;
//          attributes trend, process_variance, nugget, neg_log_likelihood
//
// A prediction is accepted inside `support`: per input, the support of a
// uniform or log-uniform distribution (the design fills it), else (normal,
// lognormal, truncated or not) the range of the training runs' values. A
// model whose training runs (/inputs/values, /samples/status of the same
// file) leave an end of a uniform or log-uniform support uncovered
// (support_coverage_problem; rover refuses to train such a model) accepts
// only the range the runs cover.
#pragma once

#include <string>
#include <vector>

#include "io/hdf5_file.hpp"
#include "study/surrogate/fitted_surrogate.hpp"

namespace rover::study {

struct SurrogateInput {
  std::string name, label;   // canonical parameter name; as the study file wrote it
  Distribution distribution;
  double lower = 0.0, upper = 0.0;  // the support predictions are accepted in
  // Non-empty when [lower, upper] is the range of the training runs that the
  // file keeps, narrower than the support it records: why.
  std::string support_note;
};

struct SurrogateSet {
  SurrogateKind kind = SurrogateKind::kPolynomialChaos;
  double q2_threshold = kDefaultQ2Threshold;
  std::vector<SurrogateInput> inputs;
  std::vector<FittedSurrogate> models;  // one per QoI
};

// The prediction support of an input from its distribution and its training values.
// A uniform or log-uniform input's training values must cover its support
// (support_coverage_problem): then the whole support is accepted.
SurrogateInput surrogate_input(const std::string& name, const std::string& label, const Distribution& distribution,
                               const Eigen::VectorXd& training_values);

// Training runs that leave an end of a uniform or log-uniform input's support
// without a run, wider than n independent draws from the distribution leave
// with this probability (both ends together; n the input's distinct values):
// the surrogate would extrapolate there. A Latin hypercube, a grid or a
// Sobol' sequence leaves at most 1/n at either end, far inside the limit.
inline constexpr double kUncoveredEndProbability = 1e-3;

// How far the training values of an input reach into its support: the range
// they cover and the share of the support (in units of the distribution's
// CDF) left without a run below and above it.
struct SupportCoverage {
  double covered_lower = 0.0, covered_upper = 0.0;
  double share_below = 0.0, share_above = 0.0;
  double largest_expected_share = 1.0;  // what n draws leave at one end but with kUncoveredEndProbability / 2
  long long distinct_values = 0;
};
SupportCoverage support_coverage(const Distribution& distribution, const Eigen::VectorXd& training_values);

// Empty when `distribution` is not uniform or log-uniform, or its training
// values cover its support as above; else what they leave uncovered, naming
// `label`, the support and the covered range.
std::string support_coverage_problem(const std::string& label, const Distribution& distribution,
                                     const Eigen::VectorXd& training_values);

void write_surrogate_set(io::Hdf5Writer& h5, const SurrogateSet& set);

// Throws io::ConfigError naming the file if it holds no /surrogate, or an
// object of the layout above is missing or malformed: every array of the
// shape the layout gives it, every number finite (a truncation bound may be
// infinite) and in its range: multi-indices whole numbers from 0 to the
// degree (at most kMaxPceDegree), length-scales, input scales and Cholesky
// diagonals positive, variances not negative. Shapes are checked before the
// data are read. Narrows the support of an input to the range of the
// training runs the file keeps where they do not cover it (above).
SurrogateSet read_surrogate_set(const std::string& path);

}  // namespace rover::study
