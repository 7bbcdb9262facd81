// Analytic test models of global sensitivity analysis, with their exact Sobol'
// indices, for checking estimators and study pipelines:
//   Ishigami & Homma (1990): f = sin x1 + a sin^2 x2 + b x3^4 sin x1, x_i ~ U(-pi, pi);
//   Sobol' g-function (Saltelli & Sobol' 1995): f = prod_i (|4 x_i - 2| + a_i) / (1 + a_i),
//     x_i ~ U(0, 1), partial variances V_i = 1 / (3 (1 + a_i)^2), V = prod (1 + V_i) - 1;
//   linear model: f = sum_i c_i x_i, x_i ~ N(0, s_i) independent, S1_i = ST_i = c_i^2 s_i^2 / V.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace rover::study {

double ishigami(const double* x, double a = 7.0, double b = 0.1);  // x_i ~ U(-pi, pi), d = 3
double sobol_g(const double* x, const std::vector<double>& a);   // x_i ~ U(0, 1), d = a.size()
double linear_model(const double* x, const std::vector<double>& coefficients);  // x_i ~ N(0, s_i)

// S2: d x d closed-form second-order indices, entries i < j filled, 0 elsewhere.
struct KnownIndices {
  Eigen::VectorXd S1, ST;
  Eigen::MatrixXd S2;
};
KnownIndices ishigami_indices(double a = 7.0, double b = 0.1);
KnownIndices sobol_g_indices(const std::vector<double>& a);  // V_i = 1/(3(1+a_i)^2), product formula
// Throws std::invalid_argument if the sizes differ or the output variance is zero.
KnownIndices linear_indices(const std::vector<double>& coefficients, const std::vector<double>& sds);

}  // namespace rover::study
