// The regression matrix of a polynomial chaos expansion (Sudret 2008):
// Psi(r, k) = prod_i phi_{alpha_k,i}(xi_i(x_ri)), the k-th multivariate
// orthonormal polynomial at run r, each input mapped to its germ and family
// (orthonormal_polynomials.hpp).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"
#include "study/estimators/distributions.hpp"
#include "study/surrogate/multi_index_set.hpp"

namespace rover::study {

// runs x terms. x: runs x inputs in physical units. Assumes the sizes agree.
Eigen::MatrixXd pce_basis_matrix(const DesignMatrix& x, const std::vector<Distribution>& inputs,
                                 const std::vector<MultiIndex>& multi_indices);

}  // namespace rover::study
