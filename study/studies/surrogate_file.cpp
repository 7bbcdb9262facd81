// See surrogate_file.hpp.
#include "study/studies/surrogate_file.hpp"
#include "study/studies/report_format.hpp"

#include <algorithm>
#include <cmath>

#include "io/json_reader.hpp"

namespace rover::study {
namespace {

constexpr DistributionKind kDistributionKinds[] = {DistributionKind::kFixed, DistributionKind::kUniform,
                                                   DistributionKind::kLogUniform, DistributionKind::kNormal,
                                                   DistributionKind::kLognormal};
constexpr int kDistributionParameters = 4;  // a, b, lower, upper


Eigen::VectorXd read_vector(const io::Hdf5Reader& h5, const std::string& dataset) {
  const std::vector<double> v = h5.read_doubles(dataset);
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

std::string model_group(const std::string& output) { return "/surrogate/models/" + output; }

void write_validation(io::Hdf5Writer& h5, const std::string& g, const FittedSurrogate& m) {
  const SurrogateValidation& v = m.validation();
  h5.attribute(g, "q2_loo", v.q2_loo);
  h5.attribute(g, "test_points", static_cast<long long>(v.test_points));
  h5.attribute(g, "q2_test", v.q2_test);
  if (const std::string why = held_out_q2_undefined_reason(v); !why.empty())
    h5.attribute(g, "q2_test_undefined_reason", why);
  h5.attribute(g, "rmse_test", v.rmse_test);
  h5.attribute(g, "warning", v.warning);
  h5.attribute(g, "runs", static_cast<long long>(m.runs()));
}

SurrogateValidation read_validation(const io::Hdf5Reader& h5, const std::string& g) {
  SurrogateValidation v;
  v.q2_loo = h5.attribute_double(g, "q2_loo");
  v.test_points = static_cast<int>(h5.attribute_integer(g, "test_points"));
  v.q2_test = h5.attribute_double(g, "q2_test");
  v.rmse_test = h5.attribute_double(g, "rmse_test");
  v.warning = h5.attribute_string(g, "warning");
  return v;
}

void write_pce(io::Hdf5Writer& h5, const std::string& g, const PolynomialChaosExpansion& e) {
  Eigen::MatrixXd alpha(static_cast<Eigen::Index>(e.multi_indices.size()), static_cast<Eigen::Index>(e.inputs.size()));
  for (std::size_t k = 0; k < e.multi_indices.size(); ++k)
    for (std::size_t i = 0; i < e.inputs.size(); ++i)
      alpha(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = e.multi_indices[k][i];
  h5.write(g + "/multi_indices", alpha);
  h5.write(g + "/coefficients", to_vector(e.coefficients));
  h5.attribute(g, "degree", static_cast<long long>(e.degree));
  h5.attribute(g, "q_norm", e.q_norm);
  h5.attribute(g, "candidate_terms", static_cast<long long>(e.candidate_terms));
  h5.attribute(g, "constant_output", static_cast<long long>(e.constant_output ? 1 : 0));
}

PolynomialChaosExpansion read_pce(const io::Hdf5Reader& h5, const std::string& g, const std::string& name,
                                  const std::vector<Distribution>& inputs) {
  PolynomialChaosExpansion e;
  e.output_name = name;
  e.inputs = inputs;
  for (const Distribution& d : inputs) e.families.push_back(polynomial_family_for(d));
  const Eigen::MatrixXd alpha = h5.read_matrix(g + "/multi_indices");
  e.coefficients = read_vector(h5, g + "/coefficients");
  if (alpha.cols() != static_cast<Eigen::Index>(inputs.size()) || alpha.rows() != e.coefficients.size())
    throw io::ConfigError(h5.path() + ": " + g + ": " + std::to_string(alpha.rows()) + " x " +
                          std::to_string(alpha.cols()) + " multi-indices for " + std::to_string(e.coefficients.size()) +
                          " coefficients and " + std::to_string(inputs.size()) + " inputs");
  for (Eigen::Index k = 0; k < alpha.rows(); ++k) {
    MultiIndex index(inputs.size());
    for (Eigen::Index i = 0; i < alpha.cols(); ++i) index[static_cast<std::size_t>(i)] = static_cast<int>(alpha(k, i));
    e.multi_indices.push_back(std::move(index));
  }
  e.degree = static_cast<int>(h5.attribute_integer(g, "degree"));
  e.q_norm = h5.attribute_double(g, "q_norm");
  e.candidate_terms = static_cast<int>(h5.attribute_integer(g, "candidate_terms"));
  e.constant_output = h5.attribute_integer(g, "constant_output") != 0;
  e.runs = static_cast<int>(h5.attribute_integer(g, "runs"));
  e.validation = read_validation(h5, g);
  return e;
}

void write_gp(io::Hdf5Writer& h5, const std::string& g, const GaussianProcess& gp) {
  h5.write(g + "/input_offset", to_vector(gp.input_offset.transpose()));
  h5.write(g + "/input_scale", to_vector(gp.input_scale.transpose()));
  h5.write(g + "/length_scales", to_vector(gp.length_scales));
  h5.write(g + "/scaled_inputs", Eigen::MatrixXd(gp.scaled_inputs));
  h5.write(g + "/trend_coefficients", to_vector(gp.trend_coefficients));
  h5.write(g + "/weights", to_vector(gp.weights));
  h5.write(g + "/loo_mean", to_vector(gp.loo_mean));
  h5.write(g + "/loo_variance", to_vector(gp.loo_variance));
  h5.write(g + "/correlation_cholesky", gp.correlation_cholesky);
  h5.write(g + "/trend_cholesky", gp.trend_cholesky);
  h5.write(g + "/whitened_trend", gp.whitened_trend);
  h5.attribute(g, "trend", gp.trend == KrigingTrend::kConstant ? "constant" : "linear");
  h5.attribute(g, "process_variance", gp.process_variance);
  h5.attribute(g, "nugget", gp.nugget);
  h5.attribute(g, "neg_log_likelihood", gp.neg_log_likelihood);
}

GaussianProcess read_gp(const io::Hdf5Reader& h5, const std::string& g, const std::string& name) {
  GaussianProcess gp;
  gp.output_name = name;
  gp.trend = h5.attribute_string(g, "trend") == "linear" ? KrigingTrend::kLinear : KrigingTrend::kConstant;
  gp.input_offset = read_vector(h5, g + "/input_offset").transpose();
  gp.input_scale = read_vector(h5, g + "/input_scale").transpose();
  gp.length_scales = read_vector(h5, g + "/length_scales");
  gp.scaled_inputs = h5.read_matrix(g + "/scaled_inputs");
  gp.trend_coefficients = read_vector(h5, g + "/trend_coefficients");
  gp.weights = read_vector(h5, g + "/weights");
  gp.loo_mean = read_vector(h5, g + "/loo_mean");
  gp.loo_variance = read_vector(h5, g + "/loo_variance");
  gp.correlation_cholesky = h5.read_matrix(g + "/correlation_cholesky");
  gp.trend_cholesky = h5.read_matrix(g + "/trend_cholesky");
  gp.whitened_trend = h5.read_matrix(g + "/whitened_trend");
  gp.process_variance = h5.attribute_double(g, "process_variance");
  gp.nugget = h5.attribute_double(g, "nugget");
  gp.neg_log_likelihood = h5.attribute_double(g, "neg_log_likelihood");
  gp.runs = static_cast<int>(h5.attribute_integer(g, "runs"));
  gp.validation = read_validation(h5, g);
  return gp;
}

void write_inputs(io::Hdf5Writer& h5, const std::vector<SurrogateInput>& inputs) {
  std::vector<std::string> names, labels, kinds;
  Eigen::MatrixXd parameters(static_cast<Eigen::Index>(inputs.size()), kDistributionParameters);
  Eigen::MatrixXd support(static_cast<Eigen::Index>(inputs.size()), 2);
  for (std::size_t j = 0; j < inputs.size(); ++j) {
    const SurrogateInput& in = inputs[j];
    const auto row = static_cast<Eigen::Index>(j);
    names.push_back(in.name);
    labels.push_back(in.label);
    kinds.push_back(distribution_name(in.distribution.kind));
    parameters.row(row) << in.distribution.a, in.distribution.b, in.distribution.lower, in.distribution.upper;
    support.row(row) << in.lower, in.upper;
  }
  h5.write("/surrogate/inputs/names", names);
  h5.write("/surrogate/inputs/labels", labels);
  h5.write("/surrogate/inputs/distribution", kinds);
  h5.write("/surrogate/inputs/parameters", parameters);
  h5.write("/surrogate/inputs/support", support);
}

std::vector<SurrogateInput> read_inputs(const io::Hdf5Reader& h5) {
  const std::vector<std::string> names = h5.read_strings("/surrogate/inputs/names");
  const std::vector<std::string> labels = h5.read_strings("/surrogate/inputs/labels");
  const std::vector<std::string> kinds = h5.read_strings("/surrogate/inputs/distribution");
  const Eigen::MatrixXd parameters = h5.read_matrix("/surrogate/inputs/parameters");
  const Eigen::MatrixXd support = h5.read_matrix("/surrogate/inputs/support");
  const auto d = static_cast<Eigen::Index>(names.size());
  if (labels.size() != names.size() || kinds.size() != names.size() || parameters.rows() != d ||
      parameters.cols() != kDistributionParameters || support.rows() != d || support.cols() != 2)
    throw io::ConfigError(h5.path() + ": /surrogate/inputs: the names, labels, distributions, parameters and "
                          "support disagree in size");
  std::vector<SurrogateInput> inputs;
  for (Eigen::Index j = 0; j < d; ++j) {
    const auto k = static_cast<std::size_t>(j);
    SurrogateInput in{names[k], labels[k], {}, support(j, 0), support(j, 1)};
    const auto kind = std::find_if(std::begin(kDistributionKinds), std::end(kDistributionKinds),
                                   [&](DistributionKind c) { return kinds[k] == distribution_name(c); });
    if (kind == std::end(kDistributionKinds))
      throw io::ConfigError(h5.path() + ": /surrogate/inputs/distribution: unknown distribution '" + kinds[k] +
                            "' of input '" + labels[k] + "'");
    in.distribution = {*kind, parameters(j, 0), parameters(j, 1), parameters(j, 2), parameters(j, 3)};
    std::string why;
    if (!in.distribution.IsValid(&why))
      throw io::ConfigError(h5.path() + ": /surrogate/inputs/parameters of '" + labels[k] + "': " + why);
    inputs.push_back(std::move(in));
  }
  return inputs;
}

// A uniform or log-uniform input: the design spreads its runs over the whole
// (finite) support. A normal or lognormal one, truncated or not, has tails
// the runs rarely reach: a finite end of its support (a lognormal's 0, a
// truncation bound) may lie far beyond every run.
bool design_fills_support(const Distribution& distribution) {
  return distribution.kind == DistributionKind::kUniform || distribution.kind == DistributionKind::kLogUniform ||
         distribution.kind == DistributionKind::kFixed;
}

}  // namespace

SurrogateInput surrogate_input(const std::string& name, const std::string& label, const Distribution& distribution,
                               const Eigen::VectorXd& training_values) {
  if (design_fills_support(distribution))
    return {name, label, distribution, distribution.support_lower(), distribution.support_upper()};
  return {name, label, distribution, training_values.minCoeff(), training_values.maxCoeff()};
}

void write_surrogate_set(io::Hdf5Writer& h5, const SurrogateSet& set) {
  h5.create_group("/surrogate");
  h5.attribute("/surrogate", "kind", surrogate_kind_name(set.kind));
  h5.attribute("/surrogate", "q2_threshold", set.q2_threshold);
  write_inputs(h5, set.inputs);
  std::vector<std::string> outputs;
  for (const FittedSurrogate& m : set.models) {
    const std::string g = model_group(m.output_name());
    outputs.push_back(m.output_name());
    h5.create_group(g);
    if (m.kind == SurrogateKind::kPolynomialChaos) write_pce(h5, g, m.pce);
    else write_gp(h5, g, m.gp);
    write_validation(h5, g, m);
  }
  h5.write("/surrogate/outputs", outputs);
}

SurrogateSet read_surrogate_set(const std::string& path) {
  const io::Hdf5Reader h5(path);
  if (!h5.exists("/surrogate/inputs") || !h5.exists("/surrogate/outputs"))
    throw io::ConfigError(path + ": no /surrogate/inputs and /surrogate/outputs: not a model written by "
                          "`rover surrogate --study`, or one damaged since it was written (write it again)");
  SurrogateSet set;
  try {
    set.kind = surrogate_kind_from_name(h5.attribute_string("/surrogate", "kind"));
  } catch (const std::invalid_argument& e) {
    throw io::ConfigError(path + ": /surrogate attribute kind: " + e.what());
  }
  set.q2_threshold = h5.attribute_double("/surrogate", "q2_threshold");
  set.inputs = read_inputs(h5);
  std::vector<Distribution> distributions;
  for (const SurrogateInput& in : set.inputs) distributions.push_back(in.distribution);
  for (const std::string& name : h5.read_strings("/surrogate/outputs")) {
    const std::string g = model_group(name);
    FittedSurrogate m;
    m.kind = set.kind;
    m.inputs = distributions;
    if (set.kind == SurrogateKind::kPolynomialChaos) m.pce = read_pce(h5, g, name, distributions);
    else m.gp = read_gp(h5, g, name);
    set.models.push_back(std::move(m));
  }
  if (set.models.empty())
    throw io::ConfigError(path + ": holds no fitted model (no QoI of its study got a surrogate; its "
                          "`rover surrogate --study` said why): nothing to predict");
  return set;
}

}  // namespace rover::study
