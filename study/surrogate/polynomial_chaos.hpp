// Sparse polynomial chaos expansion (PCE) of a scalar output of independent
// inputs (Sudret 2008; Blatman & Sudret 2011):
//   Y ~ sum_k c_k Psi_k(xi(X)),  Psi_k = prod_i phi_{alpha_k,i}(xi_i),
// the phi orthonormal under each input's germ (orthonormal_polynomials.hpp).
//
// The candidate basis is the hyperbolic set of degree p and q-norm q
// (multi_index_set.hpp); terms are selected by hybrid LARS with the corrected
// leave-one-out error (lars.hpp), or the whole basis is fitted by least
// squares. With adaptive degree, p runs from min_degree upwards and stops
// once the error has not improved for `degree_patience` degrees in a row
// (or at max_degree); the best expansion is kept (Blatman & Sudret 2011, sec. 5).
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"
#include "study/estimators/distributions.hpp"
#include "study/surrogate/multi_index_set.hpp"
#include "study/surrogate/orthonormal_polynomials.hpp"
#include "study/surrogate/surrogate_validation.hpp"

namespace rover::study {

enum class BasisSelection { kHybridLars, kFullLeastSquares };

inline constexpr int kMaxPceDegree = 20;
// What a fold of the cross-validation fits afresh (CrossValidation::refits).
inline constexpr const char* kPceRefits = "terms re-selected";
inline constexpr int kMaxPceCandidateTerms = 1000000;

struct PolynomialChaosSettings {
  int max_degree = 12;         // 1 .. kMaxPceDegree
  int min_degree = 1;          // 1 .. max_degree; first degree tried when adaptive
  bool adaptive_degree = true; // false: only max_degree
  int degree_patience = 2;     // >= 1: degrees without improvement before stopping
  double q_norm = 0.75;        // (0, 1]; 1 = total degree
  BasisSelection selection = BasisSelection::kHybridLars;
  double q2_threshold = kDefaultQ2Threshold;  // validation warning below it
  // Candidate sets larger than this are not built (memory runs x terms):
  // degrees beyond it are not tried. 1 .. kMaxPceCandidateTerms.
  int max_candidate_terms = 10000;
  // Score the whole fit, not only its coefficients: refit in each fold of a
  // cross-validation with the terms and degree chosen afresh
  // (validation.reselected). The leave-one-out error keeps the selected
  // terms, so it cannot see that they were chosen on the very runs it scores,
  // and on small designs it flatters the fit. false: leave-one-out only.
  bool cross_validate_selection = true;
  // Read at every degree and every LARS step when set: once true, the fit
  // throws WorkStopped (study/estimators/work_stopped.hpp).
  const std::atomic<bool>* stop = nullptr;
};

struct PolynomialChaosExpansion {
  std::string output_name;
  std::vector<Distribution> inputs;
  std::vector<PolynomialFamily> families;  // one per input
  std::vector<MultiIndex> multi_indices;   // the selected terms; [0] is the constant
  Eigen::VectorXd coefficients;            // one per selected term
  int degree = 0;                          // p of the candidate set it was selected from
  double q_norm = 1.0;
  int candidate_terms = 0;                 // size of that candidate set
  int runs = 0;                            // training runs
  bool constant_output = false;            // y had no variance: indices undefined
  SurrogateValidation validation;          // q2_loo = 1 - corrected LOO error

  double evaluate(const double* x) const;                   // one point, physical units
  Eigen::VectorXd evaluate(const DesignMatrix& x) const;    // one value per row
};

// Throws std::invalid_argument naming the setting, its value and the accepted
// range.
void check_polynomial_chaos_settings(const PolynomialChaosSettings& settings);

// The fewest runs a fit accepts: sparse selection needs the degree-1 set
// (d_active + 1 terms, d_active the non-fixed inputs) plus 2; the full basis
// needs the size of its first candidate set plus 1.
int min_pce_runs(const std::vector<Distribution>& inputs, const PolynomialChaosSettings& settings);

// Fits the expansion, then cross-validates its selection (above).
// A constant y yields the constant term alone, q2_loo 1,
// constant_output and a warning that its sensitivity indices are undefined.
// Throws std::invalid_argument for bad settings (as above), no inputs, an
// invalid distribution, x not runs x inputs or y not one value per run, a
// non-finite y (naming the output and the run), fewer runs than min_pce_runs,
// or a first candidate set larger than max_candidate_terms.
PolynomialChaosExpansion fit_polynomial_chaos(const DesignMatrix& x, const Eigen::VectorXd& y,
                                              const std::vector<Distribution>& inputs,
                                              const PolynomialChaosSettings& settings,
                                              const std::string& output_name = "output");

// Least-squares coefficients of y on the terms of `expansion` (kept fixed).
// Returns false (and leaves *coefficients) if the design cannot resolve them.
bool refit_pce_coefficients(const PolynomialChaosExpansion& expansion, const DesignMatrix& x,
                            const Eigen::VectorXd& y, Eigen::VectorXd* coefficients);

// Scores the expansion on held-out runs and refreshes its warning.
void validate_polynomial_chaos(const DesignMatrix& x_test, const Eigen::VectorXd& y_test,
                               double q2_threshold, PolynomialChaosExpansion* expansion);

}  // namespace rover::study
