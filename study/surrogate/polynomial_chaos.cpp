// See polynomial_chaos.hpp.
#include "study/surrogate/polynomial_chaos.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "study/estimators/work_stopped.hpp"
#include "study/surrogate/lars.hpp"
#include "study/surrogate/least_squares_loo.hpp"
#include "study/surrogate/output_magnitude.hpp"
#include "study/surrogate/pce_basis.hpp"

namespace rover::study {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// An output whose sample variance is below this fraction of its squared mean
// magnitude (or exactly 0) is treated as constant.
constexpr double kConstantOutputRelativeVariance = 1e-28;

std::string value_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::vector<bool> active_inputs(const std::vector<Distribution>& inputs) {
  std::vector<bool> active(inputs.size());
  for (std::size_t i = 0; i < inputs.size(); ++i)
    active[i] = polynomial_family_for(inputs[i]) != PolynomialFamily::kConstant;
  return active;
}

double sample_variance(const Eigen::VectorXd& y) {
  return (y.array() - y.mean()).square().sum() / static_cast<double>(y.size());
}

// The mean of y without overflow: of 1e308 in every run, 1e308.
double scaled_mean(const Eigen::VectorXd& y) {
  const double scale = y.cwiseAbs().maxCoeff();
  return scale > 0.0 ? scale * (y / scale).mean() : 0.0;
}

bool is_constant(const Eigen::VectorXd& y) {
  if (y.minCoeff() == y.maxCoeff()) return true;
  const double v = sample_variance(y);
  return v == 0.0 || v <= kConstantOutputRelativeVariance * y.squaredNorm() / static_cast<double>(y.size());
}

void check_training_data(const DesignMatrix& x, const Eigen::VectorXd& y,
                         const std::vector<Distribution>& inputs, const std::string& name) {
  if (inputs.empty()) throw std::invalid_argument("polynomial chaos: no inputs");
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    std::string why;
    if (!inputs[i].IsValid(&why))
      throw std::invalid_argument("polynomial chaos: input " + std::to_string(i) + ": " + why);
  }
  if (x.cols() != static_cast<Eigen::Index>(inputs.size()) || x.rows() != y.size())
    throw std::invalid_argument(
        "polynomial chaos: design is " + std::to_string(x.rows()) + " x " +
        std::to_string(x.cols()) + " but there are " + std::to_string(inputs.size()) +
        " inputs and " + std::to_string(y.size()) + " output values; expected runs x inputs");
  for (Eigen::Index r = 0; r < y.size(); ++r)
    if (!std::isfinite(y(r)))
      throw std::invalid_argument("polynomial chaos: output '" + name + "' is not finite at run " +
                                  std::to_string(r) + "; drop failed runs before fitting");
  if (!x.allFinite()) throw std::invalid_argument("polynomial chaos: non-finite input value");
}

struct DegreeFit {
  bool ok = false;
  bool too_large = false;  // the candidate set exceeds max_candidate_terms
  std::vector<MultiIndex> terms;
  Eigen::VectorXd coefficients;
  double corrected_loo = kInf;
  int candidates = 0;
};

DegreeFit fit_degree(const DesignMatrix& x, const Eigen::VectorXd& y,
                     const std::vector<Distribution>& inputs, const PolynomialChaosSettings& s,
                     int degree, double variance) {
  DegreeFit fit;
  const std::vector<MultiIndex> candidates =
      hyperbolic_multi_indices(static_cast<int>(inputs.size()), degree, s.q_norm,
                               active_inputs(inputs), static_cast<std::size_t>(s.max_candidate_terms));
  fit.candidates = static_cast<int>(candidates.size());
  fit.too_large = fit.candidates > s.max_candidate_terms;
  if (fit.too_large) return fit;
  const Eigen::MatrixXd psi = pce_basis_matrix(x, inputs, candidates);
  if (s.selection == BasisSelection::kFullLeastSquares) {
    const LeastSquaresLoo ls = least_squares_loo(psi, y, variance);
    if (!ls.ok) return fit;
    fit = DegreeFit{true, false, candidates, ls.coefficients, ls.corrected_loo, fit.candidates};
    return fit;
  }
  const SparseSelection sel = hybrid_lars(psi, y, variance, s.stop);
  if (!sel.ok) return fit;
  fit.ok = true;
  for (const int c : sel.columns) fit.terms.push_back(candidates[c]);
  fit.coefficients = sel.coefficients;
  fit.corrected_loo = sel.corrected_loo;
  return fit;
}

// The size of the candidate set, or max_terms + 1 if it is larger.
int candidate_count(const std::vector<Distribution>& inputs, int degree, double q, int max_terms) {
  return static_cast<int>(hyperbolic_multi_indices(static_cast<int>(inputs.size()), degree, q,
                                                   active_inputs(inputs),
                                                   static_cast<std::size_t>(max_terms))
                              .size());
}

std::string too_large_message(const std::string& name, int degree, const PolynomialChaosSettings& s) {
  return "polynomial chaos: the degree-" + std::to_string(degree) + " candidate basis of '" + name +
         "' has more than max_candidate_terms = " + std::to_string(s.max_candidate_terms) +
         " terms; lower min_degree or q_norm, or raise max_candidate_terms (up to " +
         std::to_string(kMaxPceCandidateTerms) + ")";
}

PolynomialChaosExpansion constant_expansion(const Eigen::VectorXd& y,
                                            const std::vector<Distribution>& inputs,
                                            const std::string& name) {
  PolynomialChaosExpansion e;
  e.output_name = name;
  e.inputs = inputs;
  for (const Distribution& d : inputs) e.families.push_back(polynomial_family_for(d));
  e.multi_indices.push_back(MultiIndex(inputs.size(), 0));
  e.coefficients = Eigen::VectorXd::Constant(1, scaled_mean(y));
  e.candidate_terms = 1;
  e.runs = static_cast<int>(y.size());
  e.constant_output = true;
  e.validation.q2_loo = 1.0;
  e.validation.warning = "output '" + name + "' is constant (" + value_text(scaled_mean(y)) + ") over " +
                         std::to_string(y.size()) +
                         " runs: its variance is zero and its sensitivity indices are undefined";
  return e;
}

}  // namespace

void check_polynomial_chaos_settings(const PolynomialChaosSettings& s) {
  const auto fail = [](const std::string& what) {
    throw std::invalid_argument("polynomial chaos settings: " + what);
  };
  if (s.max_degree < 1 || s.max_degree > kMaxPceDegree)
    fail("max_degree " + std::to_string(s.max_degree) + " is outside [1, " +
         std::to_string(kMaxPceDegree) + "]");
  if (s.min_degree < 1 || s.min_degree > s.max_degree)
    fail("min_degree " + std::to_string(s.min_degree) + " is outside [1, max_degree = " +
         std::to_string(s.max_degree) + "]");
  if (s.degree_patience < 1)
    fail("degree_patience " + std::to_string(s.degree_patience) + " must be >= 1");
  if (!(s.q_norm > 0.0 && s.q_norm <= 1.0))
    fail("q_norm " + value_text(s.q_norm) + " is outside (0, 1]");
  if (s.max_candidate_terms < 1 || s.max_candidate_terms > kMaxPceCandidateTerms)
    fail("max_candidate_terms " + std::to_string(s.max_candidate_terms) + " is outside [1, " +
         std::to_string(kMaxPceCandidateTerms) + "]");
  if (!(s.q2_threshold <= 1.0))
    fail("q2_threshold " + value_text(s.q2_threshold) + " must be a number <= 1");
}

int min_pce_runs(const std::vector<Distribution>& inputs, const PolynomialChaosSettings& s) {
  if (s.selection == BasisSelection::kFullLeastSquares) {
    const int first = s.adaptive_degree ? s.min_degree : s.max_degree;
    return candidate_count(inputs, first, s.q_norm, s.max_candidate_terms) + 1;
  }
  return candidate_count(inputs, 1, s.q_norm, s.max_candidate_terms) + 2;
}

namespace {

// The expansion its terms and degree were selected for, with its
// leave-one-out validation.
PolynomialChaosExpansion fit_selected_expansion(const DesignMatrix& x, const Eigen::VectorXd& y,
                                                const std::vector<Distribution>& inputs,
                                                const PolynomialChaosSettings& s, const std::string& name) {
  check_training_data(x, y, inputs, name);
  const int needed = min_pce_runs(inputs, s);
  if (y.size() < needed)
    throw std::invalid_argument("polynomial chaos: " + std::to_string(y.size()) + " runs for '" +
                                name + "'; the requested basis needs at least " +
                                std::to_string(needed));
  if (is_constant(y)) return constant_expansion(y, inputs, name);
  if (const std::string problem = output_magnitude_problem(y, name); !problem.empty())
    throw std::invalid_argument("polynomial chaos: " + problem);
  const double variance = sample_variance(y);
  DegreeFit best;
  int best_degree = 0, without_improvement = 0;
  for (int p = s.adaptive_degree ? s.min_degree : s.max_degree; p <= s.max_degree; ++p) {
    if (s.selection == BasisSelection::kFullLeastSquares &&
        candidate_count(inputs, p, s.q_norm, s.max_candidate_terms) >= y.size())
      break;
    stop_if_requested(s.stop, "polynomial chaos fit");
    DegreeFit fit = fit_degree(x, y, inputs, s, p, variance);
    if (fit.too_large) {
      if (!best.ok) throw std::invalid_argument(too_large_message(name, p, s));
      break;  // higher degrees are larger still
    }
    if (fit.ok && fit.corrected_loo < best.corrected_loo) {
      best = std::move(fit);
      best_degree = p;
      without_improvement = 0;
    } else if (++without_improvement >= s.degree_patience) {
      break;
    }
  }
  if (!best.ok)
    throw std::invalid_argument("polynomial chaos: the " + std::to_string(y.size()) +
                                " runs of '" + name + "' cannot resolve the requested basis");
  PolynomialChaosExpansion e;
  e.output_name = name;
  e.inputs = inputs;
  for (const Distribution& d : inputs) e.families.push_back(polynomial_family_for(d));
  e.multi_indices = std::move(best.terms);
  e.coefficients = std::move(best.coefficients);
  e.degree = best_degree;
  e.q_norm = s.q_norm;
  e.candidate_terms = best.candidates;
  e.runs = static_cast<int>(y.size());
  e.validation.q2_loo = 1.0 - best.corrected_loo;
  e.validation.selected_terms = static_cast<int>(e.multi_indices.size());
  e.validation.training_runs = e.runs;
  return e;
}

}  // namespace

PolynomialChaosExpansion fit_polynomial_chaos(const DesignMatrix& x, const Eigen::VectorXd& y,
                                              const std::vector<Distribution>& inputs,
                                              const PolynomialChaosSettings& s,
                                              const std::string& name) {
  check_polynomial_chaos_settings(s);
  PolynomialChaosExpansion e = fit_selected_expansion(x, y, inputs, s, name);
  if (e.constant_output) return e;
  if (s.cross_validate_selection) {
    PolynomialChaosSettings refit = s;
    refit.cross_validate_selection = false;
    e.validation.reselected = cross_validate(
        x, y, min_pce_runs(inputs, s),
        [&](const DesignMatrix& x_train, const Eigen::VectorXd& y_train, const DesignMatrix& x_test) {
          return fit_polynomial_chaos(x_train, y_train, inputs, refit, name).evaluate(x_test);
        });
    e.validation.reselected.refits = kPceRefits;
  }
  flag_low_q2(name, e.runs, s.q2_threshold, &e.validation);
  return e;
}

double PolynomialChaosExpansion::evaluate(const double* x) const {
  DesignMatrix row(1, static_cast<Eigen::Index>(inputs.size()));
  for (Eigen::Index i = 0; i < row.cols(); ++i) row(0, i) = x[i];
  return evaluate(row)(0);
}

Eigen::VectorXd PolynomialChaosExpansion::evaluate(const DesignMatrix& x) const {
  if (x.cols() != static_cast<Eigen::Index>(inputs.size()))
    throw std::invalid_argument("polynomial chaos: points have " + std::to_string(x.cols()) +
                                " columns, the expansion " + std::to_string(inputs.size()) +
                                " inputs");
  return pce_basis_matrix(x, inputs, multi_indices) * coefficients;
}

bool refit_pce_coefficients(const PolynomialChaosExpansion& e, const DesignMatrix& x,
                            const Eigen::VectorXd& y, Eigen::VectorXd* coefficients) {
  return least_squares_coefficients(pce_basis_matrix(x, e.inputs, e.multi_indices), y,
                                    coefficients);
}

void validate_polynomial_chaos(const DesignMatrix& x_test, const Eigen::VectorXd& y_test,
                               double q2_threshold, PolynomialChaosExpansion* e) {
  score_held_out(y_test, e->evaluate(x_test), &e->validation);
  if (e->constant_output) return;  // keeps the "constant output" warning
  flag_low_q2(e->output_name, e->runs, q2_threshold, &e->validation);
}

}  // namespace rover::study
