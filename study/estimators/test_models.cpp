#include "study/estimators/test_models.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <boost/math/constants/constants.hpp>

namespace rover::study {

double ishigami(const double* x, double a, double b) {
  const double s1 = std::sin(x[0]), s2 = std::sin(x[1]), x3_2 = x[2] * x[2];
  return s1 + a * s2 * s2 + b * x3_2 * x3_2 * s1;
}

double sobol_g(const double* x, const std::vector<double>& a) {
  double f = 1.0;
  for (std::size_t i = 0; i < a.size(); ++i) f *= (std::abs(4.0 * x[i] - 2.0) + a[i]) / (1.0 + a[i]);
  return f;
}

double linear_model(const double* x, const std::vector<double>& coefficients) {
  double f = 0.0;
  for (std::size_t i = 0; i < coefficients.size(); ++i) f += coefficients[i] * x[i];
  return f;
}

KnownIndices ishigami_indices(double a, double b) {
  const double pi4 = std::pow(boost::math::constants::pi<double>(), 4), pi8 = pi4 * pi4;
  // E[x3^4] = pi^4 / 5, E[x3^8] = pi^8 / 9, E[sin^2 x1] = 1/2, Var(sin^2 x2) = 1/8.
  const double V1 = 0.5 * (1.0 + b * pi4 / 5.0) * (1.0 + b * pi4 / 5.0);
  const double V2 = a * a / 8.0;
  const double V13 = b * b * pi8 * (1.0 / 18.0 - 1.0 / 50.0);
  const double V = V1 + V2 + V13;
  KnownIndices k;
  k.S1 = Eigen::Vector3d(V1 / V, V2 / V, 0.0);
  k.ST = Eigen::Vector3d((V1 + V13) / V, V2 / V, V13 / V);
  k.S2 = Eigen::MatrixXd::Zero(3, 3);
  k.S2(0, 2) = V13 / V;
  return k;
}

KnownIndices sobol_g_indices(const std::vector<double>& a) {
  const auto d = static_cast<Eigen::Index>(a.size());
  Eigen::VectorXd V(d);
  for (Eigen::Index i = 0; i < d; ++i) V[i] = 1.0 / (3.0 * (1.0 + a[i]) * (1.0 + a[i]));
  const double total = (1.0 + V.array()).prod() - 1.0;
  KnownIndices k;
  k.S1 = V / total;
  k.ST.resize(d);
  for (Eigen::Index i = 0; i < d; ++i)
    k.ST[i] = V[i] * (1.0 + V.array()).prod() / (1.0 + V[i]) / total;
  k.S2 = Eigen::MatrixXd::Zero(d, d);
  for (Eigen::Index i = 0; i < d; ++i)
    for (Eigen::Index j = i + 1; j < d; ++j) k.S2(i, j) = V[i] * V[j] / total;
  return k;
}

KnownIndices linear_indices(const std::vector<double>& coefficients,
                            const std::vector<double>& sds) {
  if (coefficients.size() != sds.size())
    throw std::invalid_argument("linear_indices: " + std::to_string(coefficients.size()) +
                                " coefficients but " + std::to_string(sds.size()) +
                                " standard deviations");
  const auto d = static_cast<Eigen::Index>(coefficients.size());
  Eigen::VectorXd V(d);
  for (Eigen::Index i = 0; i < d; ++i) V[i] = coefficients[i] * coefficients[i] * sds[i] * sds[i];
  const double total = V.sum();
  if (!(total > 0.0)) throw std::invalid_argument("linear_indices: the output variance is zero");
  KnownIndices k;
  k.S1 = k.ST = V / total;
  k.S2 = Eigen::MatrixXd::Zero(d, d);
  return k;
}

}  // namespace rover::study
