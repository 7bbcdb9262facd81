// See pce_basis.hpp.
#include "study/surrogate/pce_basis.hpp"

#include <algorithm>

#include "study/surrogate/orthonormal_polynomials.hpp"

namespace rover::study {

Eigen::MatrixXd pce_basis_matrix(const DesignMatrix& x, const std::vector<Distribution>& inputs,
                                 const std::vector<MultiIndex>& multi_indices) {
  const int dims = static_cast<int>(inputs.size());
  const int terms = static_cast<int>(multi_indices.size());
  std::vector<int> top(dims, 0);
  for (const MultiIndex& alpha : multi_indices)
    for (int i = 0; i < dims; ++i) top[i] = std::max(top[i], alpha[i]);
  std::vector<PolynomialFamily> families(dims);
  for (int i = 0; i < dims; ++i) families[i] = polynomial_family_for(inputs[i]);

  Eigen::MatrixXd psi(x.rows(), terms);
  std::vector<std::vector<double>> values(dims);
  for (int i = 0; i < dims; ++i) values[i].resize(top[i] + 1);
  for (Eigen::Index r = 0; r < x.rows(); ++r) {
    for (int i = 0; i < dims; ++i)
      orthonormal_polynomial_values(families[i], to_germ(inputs[i], x(r, i)), top[i],
                                    values[i].data());
    for (int k = 0; k < terms; ++k) {
      double product = 1.0;
      for (int i = 0; i < dims; ++i) product *= values[i][multi_indices[k][i]];
      psi(r, k) = product;
    }
  }
  return psi;
}

}  // namespace rover::study
