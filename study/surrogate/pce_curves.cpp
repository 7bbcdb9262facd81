// See pce_curves.hpp.
#include "study/surrogate/pce_curves.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/SVD>

#include "study/surrogate/least_squares_loo.hpp"
#include "study/surrogate/pce_basis.hpp"
#include "study/surrogate/pce_sobol.hpp"

namespace rover::study {
namespace {

constexpr int kMaxComponents = 100;
// A sample (or component) whose variance is below this fraction of the
// largest sample variance, or of its squared mean, is constant.
constexpr double kNegligibleVariance = 1e-24;

void check_curves(const DesignMatrix& x, const Eigen::MatrixXd& y,
                  const std::vector<Distribution>& inputs, const PolynomialChaosCurvesSettings& s,
                  const std::string& name) {
  check_polynomial_chaos_settings(s.pce);
  std::ostringstream text;
  if (!(s.explained_variance > 0.0 && s.explained_variance <= 1.0))
    text << "explained_variance " << s.explained_variance << " is outside (0, 1]";
  else if (s.max_components < 1 || s.max_components > kMaxComponents)
    text << "max_components " << s.max_components << " is outside [1, " << kMaxComponents << "]";
  if (!text.str().empty())
    throw std::invalid_argument("polynomial chaos curves settings: " + text.str());
  if (inputs.empty() || x.cols() != static_cast<Eigen::Index>(inputs.size()) ||
      x.rows() != y.rows() || y.cols() < 1)
    throw std::invalid_argument("polynomial chaos curves: design is " + std::to_string(x.rows()) +
                                " x " + std::to_string(x.cols()) + ", outputs " +
                                std::to_string(y.rows()) + " x " + std::to_string(y.cols()) +
                                ", " + std::to_string(inputs.size()) +
                                " inputs; expected runs x inputs and runs x samples");
  for (Eigen::Index r = 0; r < y.rows(); ++r)
    for (Eigen::Index t = 0; t < y.cols(); ++t)
      if (!std::isfinite(y(r, t)))
        throw std::invalid_argument("polynomial chaos curves: output '" + name +
                                    "' is not finite at run " + std::to_string(r) + ", sample " +
                                    std::to_string(t) + "; drop failed runs before fitting");
}

// Adds the terms of `terms` not yet in `basis`.
void merge_terms(const std::vector<MultiIndex>& terms, std::vector<MultiIndex>* basis) {
  for (const MultiIndex& alpha : terms)
    if (std::find(basis->begin(), basis->end(), alpha) == basis->end()) basis->push_back(alpha);
}

// The shared basis: the union of the terms selected for the leading principal
// components, kept below the number of runs. Sets *components.
std::vector<MultiIndex> select_shared_basis(const DesignMatrix& x, const Eigen::MatrixXd& centred,
                                            const std::vector<Distribution>& inputs,
                                            const PolynomialChaosCurvesSettings& s,
                                            int* components) {
  std::vector<MultiIndex> basis{MultiIndex(inputs.size(), 0)};
  *components = 0;
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinU);
  const Eigen::VectorXd energy = svd.singularValues().array().square();
  const double total = energy.sum();
  if (!(total > 0.0)) return basis;
  double explained = 0.0;
  PolynomialChaosSettings component_settings = s.pce;  // only the terms are kept: no validation needed
  component_settings.cross_validate_selection = false;
  for (Eigen::Index k = 0; k < energy.size() && *components < s.max_components; ++k) {
    if (energy(k) <= kNegligibleVariance * total) break;
    const Eigen::VectorXd scores = svd.matrixU().col(k) * svd.singularValues()(k);
    const PolynomialChaosExpansion e = fit_polynomial_chaos(x, scores, inputs, component_settings, "component");
    std::vector<MultiIndex> merged = basis;
    merge_terms(e.multi_indices, &merged);
    if (static_cast<Eigen::Index>(merged.size()) >= x.rows() - 1 && *components > 0) break;
    basis = std::move(merged);
    ++*components;
    explained += energy(k) / total;
    if (explained >= s.explained_variance) break;
  }
  return basis;
}

// The lower of the LOO and held-out Q2 of each sample; constant samples 1.
Eigen::VectorXd worst_q2(const PolynomialChaosCurves& c) {
  Eigen::VectorXd q2 = c.q2_loo;
  if (c.test_points > 0)
    for (Eigen::Index t = 0; t < q2.size(); ++t)
      if (!c.constant_sample[static_cast<std::size_t>(t)]) q2(t) = std::min(q2(t), c.q2_test(t));
  return q2;
}

std::string low_q2_warning(const PolynomialChaosCurves& c, double threshold) {
  const Eigen::VectorXd q2 = worst_q2(c);
  int low = 0;
  Eigen::Index worst = 0;
  for (Eigen::Index t = 0; t < q2.size(); ++t) {
    if (q2(t) < threshold) ++low;
    if (q2(t) < q2(worst)) worst = t;
  }
  if (low == 0) return {};
  std::ostringstream text;
  text << "surrogate of '" << c.output_name << "' is not accurate enough at " << low << " of "
       << q2.size() << " samples: " << (c.test_points > 0 ? "leave-one-out or held-out" : "leave-one-out")
       << " Q2 down to " << q2(worst) << " (sample " << worst << ") < " << threshold << " from "
       << c.runs << " runs; try a larger N";
  return text.str();
}

}  // namespace

PolynomialChaosCurves fit_polynomial_chaos_curves(const DesignMatrix& x, const Eigen::MatrixXd& y,
                                                  const std::vector<Distribution>& inputs,
                                                  const PolynomialChaosCurvesSettings& s,
                                                  const std::string& name) {
  check_curves(x, y, inputs, s, name);
  const int needed = min_pce_runs(inputs, s.pce);
  if (y.rows() < needed)
    throw std::invalid_argument("polynomial chaos curves: " + std::to_string(y.rows()) +
                                " runs for '" + name + "'; the requested basis needs at least " +
                                std::to_string(needed));
  PolynomialChaosCurves c;
  c.output_name = name;
  c.inputs = inputs;
  c.runs = static_cast<int>(y.rows());
  const Eigen::MatrixXd centred = y.rowwise() - y.colwise().mean();
  c.multi_indices = select_shared_basis(x, centred, inputs, s, &c.components);
  const Eigen::VectorXd variances =
      centred.colwise().squaredNorm().transpose() / static_cast<double>(y.rows());
  const double largest = variances.maxCoeff();
  c.constant_sample.resize(static_cast<std::size_t>(y.cols()));
  for (Eigen::Index t = 0; t < y.cols(); ++t)
    c.constant_sample[t] = !(variances(t) > kNegligibleVariance * largest) ||
                           !(variances(t) > kNegligibleVariance * y.col(t).squaredNorm() / c.runs);
  const Eigen::MatrixXd psi = pce_basis_matrix(x, inputs, c.multi_indices);
  const MultiOutputLeastSquaresLoo fit = least_squares_loo(psi, y, variances);
  if (!fit.ok)
    throw std::invalid_argument("polynomial chaos curves: the " + std::to_string(y.rows()) +
                                " runs of '" + name + "' cannot resolve the shared basis");
  c.coefficients = fit.coefficients;
  c.q2_loo = (1.0 - fit.corrected_loo.array()).matrix();
  for (Eigen::Index t = 0; t < y.cols(); ++t)
    if (c.constant_sample[t]) {
      c.q2_loo(t) = 1.0;
      c.coefficients.col(t).setZero();
      c.coefficients(0, t) = y.col(t).mean();
    }
  c.warning = low_q2_warning(c, s.pce.q2_threshold);
  return c;
}

Eigen::MatrixXd PolynomialChaosCurves::evaluate(const DesignMatrix& x) const {
  if (x.cols() != static_cast<Eigen::Index>(inputs.size()))
    throw std::invalid_argument("polynomial chaos curves: points have " + std::to_string(x.cols()) +
                                " columns, the expansion " + std::to_string(inputs.size()) + " inputs");
  return pce_basis_matrix(x, inputs, multi_indices) * coefficients;
}

void validate_polynomial_chaos_curves(const DesignMatrix& x_test, const Eigen::MatrixXd& y_test,
                                      double q2_threshold, PolynomialChaosCurves* c) {
  if (y_test.rows() != x_test.rows() || y_test.cols() != c->coefficients.cols() || y_test.rows() < 1)
    throw std::invalid_argument("polynomial chaos curves validation: outputs " +
                                std::to_string(y_test.rows()) + " x " + std::to_string(y_test.cols()) +
                                " for " + std::to_string(x_test.rows()) + " runs and " +
                                std::to_string(c->coefficients.cols()) + " samples");
  const Eigen::MatrixXd predicted = c->evaluate(x_test);
  c->q2_test.resize(y_test.cols());
  c->rmse_test.resize(y_test.cols());
  for (Eigen::Index t = 0; t < y_test.cols(); ++t) {
    SurrogateValidation v;
    score_held_out(y_test.col(t), predicted.col(t), &v);
    c->q2_test(t) = v.q2_test;
    c->rmse_test(t) = v.rmse_test;
  }
  c->test_points = static_cast<int>(y_test.rows());
  c->warning = low_q2_warning(*c, q2_threshold);
}

CurveSobolIndices curve_sobol_indices(const PolynomialChaosCurves& c) {
  const Eigen::Index samples = c.coefficients.cols();
  const Eigen::Index d = static_cast<Eigen::Index>(c.inputs.size());
  CurveSobolIndices out;
  out.mean.resize(samples);
  out.sd.resize(samples);
  out.S1 = Eigen::MatrixXd::Zero(samples, d);
  out.ST = Eigen::MatrixXd::Zero(samples, d);
  out.defined.assign(static_cast<std::size_t>(samples), false);
  Eigen::VectorXd v1 = Eigen::VectorXd::Zero(d), vt = Eigen::VectorXd::Zero(d);
  double v_total = 0.0;
  for (Eigen::Index t = 0; t < samples; ++t) {
    const PceSobolIndices s = pce_sobol_indices(c.multi_indices, c.coefficients.col(t));
    out.mean(t) = s.mean;
    out.sd(t) = std::sqrt(s.variance);
    if (!s.defined || c.constant_sample[t]) {
      out.sd(t) = 0.0;
      continue;
    }
    out.defined[t] = true;
    out.S1.row(t) = s.S1.transpose();
    out.ST.row(t) = s.ST.transpose();
    v1 += s.variance * s.S1;
    vt += s.variance * s.ST;
    v_total += s.variance;
  }
  out.aggregated_defined = v_total > 0.0;
  out.aggregated_S1 = out.aggregated_defined ? Eigen::VectorXd(v1 / v_total) : Eigen::VectorXd::Zero(d);
  out.aggregated_ST = out.aggregated_defined ? Eigen::VectorXd(vt / v_total) : Eigen::VectorXd::Zero(d);
  return out;
}

}  // namespace rover::study
