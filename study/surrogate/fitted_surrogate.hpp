// One interface over the two surrogates of a scalar output, so that studies,
// files and predictions treat them alike: a sparse polynomial chaos expansion
// (polynomial_chaos.hpp) or a Gaussian process (gaussian_process.hpp).
//
// The Gaussian process is fitted on the inputs' probability-integral
// transform u_i = F_i(x_i) in [0, 1], the unit cube the designs are drawn in
// (study/design/design.hpp): a log-uniform input is spread evenly, and the
// correlation lengths are in units of probability, whatever the input's scale.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"
#include "study/estimators/distributions.hpp"
#include "study/surrogate/gaussian_process.hpp"
#include "study/surrogate/polynomial_chaos.hpp"
#include "study/surrogate/surrogate_validation.hpp"

namespace rover::study {

enum class SurrogateKind { kPolynomialChaos, kGaussianProcess };

// "pce", "gp".
const char* surrogate_kind_name(SurrogateKind kind);
// The inverse of surrogate_kind_name; throws std::invalid_argument naming the valid names.
SurrogateKind surrogate_kind_from_name(const std::string& name);

struct FittedSurrogate {
  SurrogateKind kind = SurrogateKind::kPolynomialChaos;
  std::vector<Distribution> inputs;  // the measure of the inputs (both kinds)
  PolynomialChaosExpansion pce;      // kind kPolynomialChaos
  GaussianProcess gp;                // kind kGaussianProcess, on u = F(x)

  const std::string& output_name() const;
  const SurrogateValidation& validation() const;
  SurrogateValidation& validation();
  int runs() const;
};

// Predictive mean and standard deviation (0 for a polynomial chaos), one per point.
struct SurrogatePrediction {
  Eigen::VectorXd mean, sd;
};

// u_ij = F_j(x_ij): the rows of x mapped into the unit cube by the inputs' CDFs.
DesignMatrix to_unit_cube(const DesignMatrix& x, const std::vector<Distribution>& inputs);

FittedSurrogate polynomial_chaos_surrogate(PolynomialChaosExpansion expansion);

// Fits a Gaussian process to y on F(x). Throws std::invalid_argument as
// fit_gaussian_process does (too few runs, a non-finite or constant y).
FittedSurrogate fit_gaussian_process_surrogate(const DesignMatrix& x, const Eigen::VectorXd& y,
                                               const std::vector<Distribution>& inputs,
                                               const GaussianProcessSettings& settings,
                                               const std::string& output_name);

// At the rows of x (physical units, one column per input).
SurrogatePrediction predict_surrogate(const FittedSurrogate& surrogate, const DesignMatrix& x);

// Scores the surrogate on held-out runs and refreshes its warning.
void validate_surrogate(const DesignMatrix& x_test, const Eigen::VectorXd& y_test, double q2_threshold,
                        FittedSurrogate* surrogate);

// The leave-one-out prediction of each training run (x, y: the runs it was
// fitted on). Polynomial chaos: from the leverages h_i of its selected terms,
// y_i - (y_i - yhat_i) / (1 - h_i) (Allen 1974), the uncorrected error whose
// corrected mean square gives its Q^2; a run of leverage 1 keeps yhat_i.
// Gaussian process: Dubrule's closed form (GaussianProcess::loo_mean).
Eigen::VectorXd leave_one_out_predictions(const FittedSurrogate& surrogate, const DesignMatrix& x,
                                          const Eigen::VectorXd& y);

}  // namespace rover::study
