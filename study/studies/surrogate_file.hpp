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
// lognormal, truncated or not) the range of the training runs' values.
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
};

struct SurrogateSet {
  SurrogateKind kind = SurrogateKind::kPolynomialChaos;
  double q2_threshold = kDefaultQ2Threshold;
  std::vector<SurrogateInput> inputs;
  std::vector<FittedSurrogate> models;  // one per QoI
};

// The prediction support of an input from its distribution and its training values.
SurrogateInput surrogate_input(const std::string& name, const std::string& label, const Distribution& distribution,
                               const Eigen::VectorXd& training_values);

void write_surrogate_set(io::Hdf5Writer& h5, const SurrogateSet& set);

// Throws io::ConfigError naming the file if it holds no /surrogate, or an
// object of the layout above is missing or malformed: every array of the
// shape the layout gives it, every number finite (a truncation bound may be
// infinite) and in its range: multi-indices whole numbers from 0 to the
// degree (at most kMaxPceDegree), length-scales, input scales and Cholesky
// diagonals positive, variances not negative. Shapes are checked before the
// data are read.
SurrogateSet read_surrogate_set(const std::string& path);

}  // namespace rover::study
