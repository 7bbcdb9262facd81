// See surrogate_file.hpp.
#include "study/studies/surrogate_file.hpp"
#include "study/studies/report_format.hpp"
#include "study/studies/report_number.hpp"
#include "study/studies/reselected_cross_validation_output.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/number_text.hpp"
#include "io/json_reader.hpp"
#include "io/result_label.hpp"

namespace rover::study {
namespace {

constexpr DistributionKind kDistributionKinds[] = {DistributionKind::kFixed, DistributionKind::kUniform,
                                                   DistributionKind::kLogUniform, DistributionKind::kNormal,
                                                   DistributionKind::kLognormal};
constexpr int kDistributionParameters = 4;  // a, b, lower, upper
// The largest run count a design has (1e8 samples): beyond it a count is not one rover wrote.
constexpr long long kMaxSavedRuns = 100000000;
constexpr double kMaxAbsSavedNumber = std::numeric_limits<double>::max();


// Every number of a saved model is checked as it is read, before any of it
// is used: a file that `rover surrogate --study` did not write, or that was
// edited since, is refused naming the object and the value (a multi-index of
// 1e9 would build polynomials of that degree; a NaN coefficient predicts NaN).
class SavedModel {
 public:
  static constexpr Eigen::Index kAnySize = -1;

  explicit SavedModel(const std::string& path) : h5_(path) {}
  const io::Hdf5Reader& h5() const { return h5_; }
  const std::string& path() const { return h5_.path(); }

  [[noreturn]] void refuse(const std::string& object, const std::string& problem) const {
    throw io::ConfigError(path() + ": not a model written by `rover surrogate --study`, or edited since: " + object +
                          " " + problem + " (write it again with rover surrogate --study)");
  }

  // A 2-D dataset of rows x cols (kAnySize: any), every value finite unless
  // `infinite_allowed`; its shape is checked before anything is read.
  Eigen::MatrixXd matrix(const std::string& dataset, Eigen::Index rows, Eigen::Index cols,
                         bool infinite_allowed = false) const {
    const std::vector<std::size_t> dims = h5_.shape(dataset);
    if (dims.size() != 2 || !size_fits(dims[0], rows) || !size_fits(dims[1], cols))
      refuse(dataset, "has shape " + shape_text(dims) + ", expected " + expected_text({rows, cols}));
    const Eigen::MatrixXd m = h5_.read_matrix(dataset);
    if (!infinite_allowed) refuse_non_finite(dataset, Eigen::Map<const Eigen::VectorXd>(m.data(), m.size()));
    return m;
  }
  // A 1-D dataset of `size` values (kAnySize: any), every value finite.
  Eigen::VectorXd vector(const std::string& dataset, Eigen::Index size) const {
    const std::vector<std::size_t> dims = h5_.shape(dataset);
    if (dims.size() != 1 || !size_fits(dims[0], size))
      refuse(dataset, "has shape " + shape_text(dims) + ", expected " + expected_text({size}));
    const std::vector<double> v = h5_.read_doubles(dataset);
    Eigen::VectorXd out = Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
    refuse_non_finite(dataset, out);
    return out;
  }
  // Every value of `values` (read from `object`) above `minimum` (strict) or at least it.
  void refuse_below(const std::string& object, const Eigen::Ref<const Eigen::VectorXd>& values, double minimum,
                    bool strict) const {
    for (Eigen::Index i = 0; i < values.size(); ++i)
      if (strict ? !(values(i) > minimum) : !(values(i) >= minimum))
        refuse(object, "holds " + number_text(values(i)) + " (value " + std::to_string(i) + "), expected a number " +
                           (strict ? "above " : "of at least ") + number_text(minimum));
  }
  // A finite number attribute in [lower, upper].
  double number(const std::string& object, const std::string& name, double lower, double upper) const {
    const double v = h5_.attribute_double(object, name);
    if (!(std::isfinite(v) && v >= lower && v <= upper))
      refuse(object + " attribute " + name,
             "holds " + number_text(v) + ", expected a number in [" + number_text(lower) + ", " + number_text(upper) + "]");
    return v;
  }
  // A whole-number attribute in [lower, upper].
  long long integer(const std::string& object, const std::string& name, long long lower, long long upper) const {
    const double v = h5_.attribute_double(object, name);
    if (!(v >= static_cast<double>(lower) && v <= static_cast<double>(upper) && v == std::floor(v)))
      refuse(object + " attribute " + name, "holds " + number_text(v) + ", expected a whole number from " +
                                                std::to_string(lower) + " to " + std::to_string(upper));
    return static_cast<long long>(v);
  }

 private:
  static bool size_fits(std::size_t size, Eigen::Index expected) {
    return expected == kAnySize ? size >= 1 : size == static_cast<std::size_t>(expected);
  }
  static std::string shape_text(const std::vector<std::size_t>& dims) {
    std::string text = "(";
    for (std::size_t i = 0; i < dims.size(); ++i) text += (i ? " x " : "") + std::to_string(dims[i]);
    return text + ")";
  }
  static std::string expected_text(const std::vector<Eigen::Index>& dims) {
    std::string text = "(";
    for (std::size_t i = 0; i < dims.size(); ++i)
      text += (i ? " x " : "") + (dims[i] == kAnySize ? std::string("n") : std::to_string(dims[i]));
    return text + ")";
  }
  void refuse_non_finite(const std::string& dataset, const Eigen::Ref<const Eigen::VectorXd>& values) const {
    for (Eigen::Index i = 0; i < values.size(); ++i)
      if (!std::isfinite(values(i)))
        refuse(dataset, "holds " + number_text(values(i)) + " (value " + std::to_string(i) + "), expected finite numbers");
  }

  io::Hdf5Reader h5_;
};

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
  write_reselected_cross_validation(h5, g, v.reselected);
}

SurrogateValidation read_validation(const SavedModel& f, const std::string& g) {
  SurrogateValidation v;
  v.q2_loo = f.number(g, "q2_loo", -kMaxAbsSavedNumber, 1.0);
  v.test_points = static_cast<int>(f.integer(g, "test_points", 0, kMaxSavedRuns));
  // An undefined held-out Q2 (too few or equal held-out values) is saved as NaN.
  v.q2_test = v.test_points > 0 && std::isnan(f.h5().attribute_double(g, "q2_test"))
                  ? std::numeric_limits<double>::quiet_NaN()
                  : f.number(g, "q2_test", -kMaxAbsSavedNumber, 1.0);
  v.rmse_test = f.number(g, "rmse_test", 0.0, kMaxAbsSavedNumber);
  v.warning = f.h5().attribute_string(g, "warning");
  if (f.h5().has_attribute(g, kReselectedFoldsAttribute)) {
    v.reselected.folds = static_cast<int>(f.integer(g, kReselectedFoldsAttribute, 0, kCrossValidationFolds));
    if (v.reselected.folds > 0) v.reselected.q2 = f.number(g, kReselectedQ2Attribute, -kMaxAbsSavedNumber, 1.0);
    else v.reselected.why_not = f.h5().attribute_string(g, kReselectedWhyNotAttribute);
  }
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

// The multi-indices: whole numbers from 0 to the expansion's degree.
std::vector<MultiIndex> read_multi_indices(const SavedModel& f, const std::string& g, Eigen::Index terms,
                                           std::size_t inputs, int degree) {
  const std::string dataset = g + "/multi_indices";
  const Eigen::MatrixXd alpha = f.matrix(dataset, terms, static_cast<Eigen::Index>(inputs));
  std::vector<MultiIndex> indices;
  for (Eigen::Index k = 0; k < alpha.rows(); ++k) {
    MultiIndex index(inputs);
    for (Eigen::Index i = 0; i < alpha.cols(); ++i) {
      const double a = alpha(k, i);
      if (!(a >= 0.0 && a <= degree && a == std::floor(a)))
        f.refuse(dataset, "holds " + number_text(a) + " (term " + std::to_string(k) + ", input " + std::to_string(i) +
                              "), expected a whole number from 0 to the expansion's degree " + std::to_string(degree));
      index[static_cast<std::size_t>(i)] = static_cast<int>(a);
    }
    indices.push_back(std::move(index));
  }
  return indices;
}

PolynomialChaosExpansion read_pce(const SavedModel& f, const std::string& g, const std::string& name,
                                  const std::vector<Distribution>& inputs) {
  PolynomialChaosExpansion e;
  e.output_name = name;
  e.inputs = inputs;
  for (const Distribution& d : inputs) e.families.push_back(polynomial_family_for(d));
  e.degree = static_cast<int>(f.integer(g, "degree", 0, kMaxPceDegree));
  e.coefficients = f.vector(g + "/coefficients", SavedModel::kAnySize);
  if (e.coefficients.size() > kMaxPceCandidateTerms)
    f.refuse(g + "/coefficients", "holds " + std::to_string(e.coefficients.size()) + " terms, more than a fit keeps (" +
                                      std::to_string(kMaxPceCandidateTerms) + ")");
  e.multi_indices = read_multi_indices(f, g, e.coefficients.size(), inputs.size(), e.degree);
  e.q_norm = f.number(g, "q_norm", std::numeric_limits<double>::min(), 1.0);
  e.candidate_terms = static_cast<int>(f.integer(g, "candidate_terms", 0, kMaxPceCandidateTerms));
  e.constant_output = f.integer(g, "constant_output", 0, 1) != 0;
  e.runs = static_cast<int>(f.integer(g, "runs", 1, kMaxSavedRuns));
  e.validation = read_validation(f, g);
  e.validation.selected_terms = static_cast<int>(e.multi_indices.size());
  e.validation.training_runs = e.runs;
  e.validation.reselected.refits = kPceRefits;
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

// A lower-triangular Cholesky factor of rows x rows: its diagonal positive.
Eigen::MatrixXd read_cholesky(const SavedModel& f, const std::string& dataset, Eigen::Index rows) {
  Eigen::MatrixXd l = f.matrix(dataset, rows, rows);
  f.refuse_below(dataset + " (its diagonal)", l.diagonal(), 0.0, /*strict=*/true);
  return l;
}

GaussianProcess read_gp(const SavedModel& f, const std::string& g, const std::string& name, std::size_t inputs) {
  GaussianProcess gp;
  gp.output_name = name;
  const std::string trend = f.h5().attribute_string(g, "trend");
  if (trend != "constant" && trend != "linear")
    f.refuse(g + " attribute trend", "holds '" + trend + "', expected \"constant\" or \"linear\"");
  gp.trend = trend == "linear" ? KrigingTrend::kLinear : KrigingTrend::kConstant;
  const auto d = static_cast<Eigen::Index>(inputs);
  const Eigen::Index p = gp.trend == KrigingTrend::kLinear ? d + 1 : 1;
  gp.input_offset = f.vector(g + "/input_offset", d).transpose();
  gp.input_scale = f.vector(g + "/input_scale", d).transpose();
  f.refuse_below(g + "/input_scale", gp.input_scale.transpose(), 0.0, /*strict=*/true);
  gp.length_scales = f.vector(g + "/length_scales", d);
  f.refuse_below(g + "/length_scales", gp.length_scales, 0.0, /*strict=*/true);
  gp.scaled_inputs = f.matrix(g + "/scaled_inputs", SavedModel::kAnySize, d);
  const Eigen::Index n = gp.scaled_inputs.rows();
  gp.trend_coefficients = f.vector(g + "/trend_coefficients", p);
  gp.weights = f.vector(g + "/weights", n);
  gp.loo_mean = f.vector(g + "/loo_mean", n);
  gp.loo_variance = f.vector(g + "/loo_variance", n);
  f.refuse_below(g + "/loo_variance", gp.loo_variance, 0.0, /*strict=*/false);
  gp.correlation_cholesky = read_cholesky(f, g + "/correlation_cholesky", n);
  gp.trend_cholesky = read_cholesky(f, g + "/trend_cholesky", p);
  gp.whitened_trend = f.matrix(g + "/whitened_trend", n, p);
  gp.process_variance = f.number(g, "process_variance", 0.0, kMaxAbsSavedNumber);
  gp.nugget = f.number(g, "nugget", 0.0, kMaxAbsSavedNumber);
  gp.neg_log_likelihood = f.number(g, "neg_log_likelihood", -kMaxAbsSavedNumber, kMaxAbsSavedNumber);
  gp.runs = static_cast<int>(f.integer(g, "runs", n, n));
  gp.validation = read_validation(f, g);
  gp.validation.training_runs = gp.runs;
  gp.validation.reselected.refits = kGpRefits;
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

// A string dataset of `size` entries.
std::vector<std::string> read_names(const SavedModel& f, const std::string& dataset, std::size_t size) {
  const std::vector<std::string> names = f.h5().read_strings(dataset);
  if (names.size() != size)
    f.refuse(dataset, "holds " + std::to_string(names.size()) + " entries for " + std::to_string(size) + " inputs");
  return names;
}

std::vector<SurrogateInput> read_inputs(const SavedModel& f) {
  const std::vector<std::string> names = f.h5().read_strings("/surrogate/inputs/names");
  if (names.empty()) f.refuse("/surrogate/inputs/names", "is empty: a surrogate has inputs");
  const std::vector<std::string> labels = read_names(f, "/surrogate/inputs/labels", names.size());
  const std::vector<std::string> kinds = read_names(f, "/surrogate/inputs/distribution", names.size());
  const auto d = static_cast<Eigen::Index>(names.size());
  // Untruncated sides are saved as infinite bounds (Distribution::IsValid checks the rest).
  const Eigen::MatrixXd parameters = f.matrix("/surrogate/inputs/parameters", d, kDistributionParameters, true);
  const Eigen::MatrixXd support = f.matrix("/surrogate/inputs/support", d, 2);
  std::vector<SurrogateInput> inputs;
  for (Eigen::Index j = 0; j < d; ++j) {
    const auto k = static_cast<std::size_t>(j);
    SurrogateInput in{names[k], labels[k], {}, support(j, 0), support(j, 1), ""};
    for (const std::string& name : {in.name, in.label})
      if (const std::string problem = io::result_label_problem(name); !problem.empty())
        f.refuse("/surrogate/inputs", "names an input " + problem);
    if (!(in.lower <= in.upper))
      f.refuse("/surrogate/inputs/support", "of '" + labels[k] + "' is [" + number_text(in.lower) + ", " +
                                                number_text(in.upper) + "], reversed");
    const auto kind = std::find_if(std::begin(kDistributionKinds), std::end(kDistributionKinds),
                                   [&](DistributionKind c) { return kinds[k] == distribution_name(c); });
    if (kind == std::end(kDistributionKinds))
      f.refuse("/surrogate/inputs/distribution", "holds the unknown distribution '" + kinds[k] + "' of input '" +
                                                     labels[k] + "'");
    in.distribution = {*kind, parameters(j, 0), parameters(j, 1), parameters(j, 2), parameters(j, 3)};
    std::string why;
    if (!in.distribution.IsValid(&why)) f.refuse("/surrogate/inputs/parameters", "of '" + labels[k] + "': " + why);
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

// The successful training runs the model file keeps (/inputs/names and
// /inputs/values, /samples/status): where they leave an end of a uniform or
// log-uniform input's support uncovered, the input accepts only the range
// they cover. A file without them (or with runs of other inputs) is left as it is.
void narrow_to_training_runs(const io::Hdf5Reader& h5, std::vector<SurrogateInput>& inputs) {
  if (!h5.exists("/inputs/names") || !h5.exists("/inputs/values")) return;
  const std::vector<std::string> names = h5.read_strings("/inputs/names");
  const Eigen::MatrixXd values = h5.read_matrix("/inputs/values");
  if (values.cols() != static_cast<Eigen::Index>(names.size())) return;
  std::vector<int> status = h5.exists("/samples/status") ? h5.read_ints("/samples/status")
                                                         : std::vector<int>(static_cast<std::size_t>(values.rows()), 0);
  if (static_cast<Eigen::Index>(status.size()) != values.rows()) return;
  for (SurrogateInput& in : inputs) {
    const auto column = std::find_if(names.begin(), names.end(),
                                     [&](const std::string& n) { return n == in.name || n == in.label; });
    if (column == names.end()) continue;
    std::vector<double> ok;
    for (Eigen::Index i = 0; i < values.rows(); ++i)
      if (status[static_cast<std::size_t>(i)] == 0) ok.push_back(values(i, column - names.begin()));
    const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(ok.data(), static_cast<Eigen::Index>(ok.size()));
    const std::string problem = support_coverage_problem(in.label, in.distribution, v);
    if (problem.empty()) continue;
    in.lower = std::max(in.lower, v.minCoeff());
    in.upper = std::min(in.upper, v.maxCoeff());
    in.support_note = "the range its training runs cover, narrower than its declared support [" +
                      number_text(in.distribution.support_lower()) + ", " +
                      number_text(in.distribution.support_upper()) + "]";
  }
}

}  // namespace

SupportCoverage support_coverage(const Distribution& distribution, const Eigen::VectorXd& training_values) {
  SupportCoverage c;
  std::vector<double> values(training_values.data(), training_values.data() + training_values.size());
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  c.distinct_values = static_cast<long long>(values.size());
  if (values.empty()) return c;
  c.covered_lower = values.front();
  c.covered_upper = values.back();
  c.share_below = std::clamp(distribution.cdf(c.covered_lower), 0.0, 1.0);
  c.share_above = std::clamp(1.0 - distribution.cdf(c.covered_upper), 0.0, 1.0);
  // n independent draws leave more than g at one end with probability (1 - g)^n.
  c.largest_expected_share =
      1.0 - std::pow(kUncoveredEndProbability / 2.0, 1.0 / static_cast<double>(c.distinct_values));
  return c;
}

std::string support_coverage_problem(const std::string& label, const Distribution& distribution,
                                     const Eigen::VectorXd& training_values) {
  if (distribution.kind != DistributionKind::kUniform && distribution.kind != DistributionKind::kLogUniform)
    return "";
  const SupportCoverage c = support_coverage(distribution, training_values);
  if (c.distinct_values == 0) return "";
  const bool below = c.share_below > c.largest_expected_share, above = c.share_above > c.largest_expected_share;
  if (!below && !above) return "";
  auto percent = [](double share) { return format_number(100.0 * share, 2) + " %"; };
  std::string gaps;
  if (below) gaps = percent(c.share_below) + " below " + number_text(c.covered_lower);
  if (above) gaps += (gaps.empty() ? "" : " and ") + percent(c.share_above) + " above " + number_text(c.covered_upper);
  return "'" + label + "': the training runs cover " + number_text(c.covered_lower) + " to " +
         number_text(c.covered_upper) + " of its declared support [" + number_text(distribution.support_lower()) +
         ", " + number_text(distribution.support_upper()) + "] (" + distribution.describe() + "), leaving " + gaps +
         " of its probability without a run, where " + std::to_string(c.distinct_values) +
         " draws from it leave at most " + percent(c.largest_expected_share) +
         " at either end (but once in 2000): the surrogate would extrapolate there, and its mean, sd and indices "
         "integrate over the whole support. Train on runs that cover the support, or declare the support the runs "
         "cover";
}

SurrogateInput surrogate_input(const std::string& name, const std::string& label, const Distribution& distribution,
                               const Eigen::VectorXd& training_values) {
  if (design_fills_support(distribution))
    return {name, label, distribution, distribution.support_lower(), distribution.support_upper(), ""};
  return {name, label, distribution, training_values.minCoeff(), training_values.maxCoeff(), ""};
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
  const SavedModel f(path);
  const io::Hdf5Reader& h5 = f.h5();
  if (!h5.exists("/surrogate/inputs") || !h5.exists("/surrogate/outputs")) {
    if (h5.has_attribute("/", "study") && h5.attribute_string("/", "study") != "surrogate")
      throw io::ConfigError(path + ": a " + h5.attribute_string("/", "study") +
                            " result, not a surrogate model: give the file written by `rover surrogate --study`");
    throw io::ConfigError(path + ": no /surrogate/inputs and /surrogate/outputs: not a model written by "
                          "`rover surrogate --study`, or one damaged since it was written (write it again)");
  }
  SurrogateSet set;
  try {
    set.kind = surrogate_kind_from_name(h5.attribute_string("/surrogate", "kind"));
  } catch (const std::invalid_argument& e) {
    throw io::ConfigError(path + ": /surrogate attribute kind: " + e.what());
  }
  set.q2_threshold = f.number("/surrogate", "q2_threshold", std::numeric_limits<double>::min(), 1.0);
  set.inputs = read_inputs(f);
  std::vector<Distribution> distributions;
  for (const SurrogateInput& in : set.inputs) distributions.push_back(in.distribution);
  std::vector<std::string> outputs;
  for (const std::string& name : h5.read_strings("/surrogate/outputs")) {
    if (const std::string problem = io::result_label_problem(name); !problem.empty())
      f.refuse("/surrogate/outputs", "names a QoI " + problem);
    if (std::find(outputs.begin(), outputs.end(), name) != outputs.end())
      f.refuse("/surrogate/outputs", "names '" + name + "' twice");
    outputs.push_back(name);
    const std::string g = model_group(name);
    FittedSurrogate m;
    m.kind = set.kind;
    m.inputs = distributions;
    if (set.kind == SurrogateKind::kPolynomialChaos) m.pce = read_pce(f, g, name, distributions);
    else m.gp = read_gp(f, g, name, distributions.size());
    m.validation().q2_threshold = set.q2_threshold;
    set.models.push_back(std::move(m));
  }
  if (set.models.empty())
    throw io::ConfigError(path + ": holds no fitted model (no QoI of its study got a surrogate; its "
                          "`rover surrogate --study` said why): nothing to predict");
  narrow_to_training_runs(h5, set.inputs);
  return set;
}

}  // namespace rover::study
