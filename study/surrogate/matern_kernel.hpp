// The anisotropic Matern 5/2 correlation (Rasmussen & Williams 2006, eq. 4.17):
//   k(r) = (1 + sqrt5 r + 5 r^2 / 3) exp(-sqrt5 r),
//   r^2  = sum_i ((x_i - x'_i) / l_i)^2,
// twice mean-square differentiable: smooth responses without the Gaussian
// kernel's ill-conditioning (Stein 1999).
#pragma once

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"

namespace rover::study {

double matern52(double r);

// R(a, b) = k(r(a_i, b_j)), rows of a against rows of b; length_scales one per column.
Eigen::MatrixXd matern52_correlation(const DesignMatrix& a, const DesignMatrix& b,
                                     const Eigen::VectorXd& length_scales);

}  // namespace rover::study
