// Polynomial chaos of a curve (an output sampled at T times or points) on one
// shared basis, and its Sobol' indices per sample (Nagel, Rieckermann &
// Sudret 2020, principal-component PCE; Sudret 2008 for the indices).
//
// The runs x T outputs are centred and reduced by principal components (the
// thin SVD); a sparse PCE (polynomial_chaos.hpp) is selected for each of the
// leading components that together explain `explained_variance` of the total
// variance; the union of their terms is the shared basis, and every sample
// is refitted on it by least squares, with its own corrected LOO error. From
// the coefficients: mean(t), sd(t), S1_i(t), ST_i(t), and the
// variance-weighted aggregated indices (Gamboa, Janon, Klein & Lagnoux 2014;
// Lamboni, Monod & Makowski 2011):
//   S_i^agg = sum_t V_t S_i(t) / sum_t V_t.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"
#include "study/estimators/distributions.hpp"
#include "study/surrogate/multi_index_set.hpp"
#include "study/surrogate/polynomial_chaos.hpp"

namespace rover::study {

struct PolynomialChaosCurvesSettings {
  PolynomialChaosSettings pce;       // per-component selection settings
  double explained_variance = 0.99;  // (0, 1]
  int max_components = 10;           // 1 .. 100
};

struct PolynomialChaosCurves {
  std::string output_name;
  std::vector<Distribution> inputs;
  std::vector<MultiIndex> multi_indices;  // the shared basis; [0] is the constant
  Eigen::MatrixXd coefficients;           // terms x samples
  Eigen::VectorXd q2_loo;                 // per sample: 1 - corrected LOO error
  std::vector<bool> constant_sample;      // samples with no variance over the runs
  int components = 0;                     // principal components the basis was selected on
  int runs = 0;
  std::string warning;                    // empty, or which samples fall below the Q2 threshold
  // Held-out validation (validate_polynomial_chaos_curves); empty until then.
  Eigen::VectorXd q2_test, rmse_test;     // per sample
  int test_points = 0;

  Eigen::MatrixXd evaluate(const DesignMatrix& x) const;  // rows of x x samples
};

// y: runs x samples. Throws std::invalid_argument for bad settings (naming
// them), mismatched sizes, a non-finite value (naming run and sample), or too
// few runs (min_pce_runs of the settings).
PolynomialChaosCurves fit_polynomial_chaos_curves(const DesignMatrix& x, const Eigen::MatrixXd& y,
                                                  const std::vector<Distribution>& inputs,
                                                  const PolynomialChaosCurvesSettings& settings,
                                                  const std::string& output_name = "output");

// Scores the curves on held-out runs (rows of x_test, y_test: runs x
// samples), per sample, and refreshes the warning (the LOO and held-out Q2
// of every non-constant sample against the threshold). Throws
// std::invalid_argument for mismatched sizes or non-finite values.
void validate_polynomial_chaos_curves(const DesignMatrix& x_test, const Eigen::MatrixXd& y_test,
                                      double q2_threshold, PolynomialChaosCurves* curves);

struct CurveSobolIndices {
  Eigen::VectorXd mean, sd;     // per sample
  Eigen::MatrixXd S1, ST;       // samples x inputs; rows of undefined samples are 0
  std::vector<bool> defined;    // false where the sample has no variance
  bool aggregated_defined = false;  // false when no sample varies
  Eigen::VectorXd aggregated_S1, aggregated_ST;  // inputs each; 0 when undefined
};

CurveSobolIndices curve_sobol_indices(const PolynomialChaosCurves& curves);

}  // namespace rover::study
