// See matern_kernel.hpp.
#include "study/surrogate/matern_kernel.hpp"

#include <cmath>

namespace rover::study {
namespace {

const double kSqrt5 = std::sqrt(5.0);
constexpr double kFiveThirds = 5.0 / 3.0;

}  // namespace

double matern52(double r) { return (1.0 + kSqrt5 * r + kFiveThirds * r * r) * std::exp(-kSqrt5 * r); }

Eigen::MatrixXd matern52_correlation(const DesignMatrix& a, const DesignMatrix& b,
                                     const Eigen::VectorXd& length_scales) {
  const Eigen::RowVectorXd inverse = length_scales.cwiseInverse().transpose();
  const DesignMatrix as = a.array().rowwise() * inverse.array();
  const DesignMatrix bs = b.array().rowwise() * inverse.array();
  Eigen::MatrixXd r(a.rows(), b.rows());
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < b.rows(); ++j) r(i, j) = matern52((as.row(i) - bs.row(j)).norm());
  return r;
}

}  // namespace rover::study
