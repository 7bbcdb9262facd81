// Replicate errors of prefix estimates and their power-law fit: see
// study/estimators/replicate_error.hpp.
#include "study/estimators/replicate_error.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/LU>
#include <Eigen/QR>

namespace rover::study {
namespace {

void require_prefix(int n, Eigen::Index available, const char* what) {
  if (n < 2 || n > available)
    throw std::invalid_argument(std::string(what) + ": a prefix of n = " + std::to_string(n) +
                                " needs 2 <= n <= " + std::to_string(available));
}

}  // namespace

SampleMoments prefix_moments(std::span<const double> values, int n) {
  require_prefix(n, static_cast<Eigen::Index>(values.size()), "prefix_moments");
  const Eigen::Map<const Eigen::VectorXd> x(values.data(), n);
  if (!x.allFinite()) throw std::invalid_argument("prefix_moments: a value among the first n is not finite");
  const double mean = x.mean();
  return {mean, std::sqrt((x.array() - mean).square().sum() / (n - 1))};
}

CurveMoments prefix_curve_moments(const Eigen::Ref<const Eigen::MatrixXd>& curves, int n) {
  require_prefix(n, curves.rows(), "prefix_curve_moments");
  const auto rows = curves.topRows(n);
  if (!rows.allFinite())
    throw std::invalid_argument("prefix_curve_moments: a value in the first n rows is not finite");
  CurveMoments m;
  m.mean = rows.colwise().mean().transpose();
  m.sd = ((rows.rowwise() - m.mean.transpose()).colwise().squaredNorm().transpose() / (n - 1)).cwiseSqrt();
  return m;
}

std::vector<int> power_of_two_sizes(int n_min, int n_max) {
  if (n_min < 1) throw std::invalid_argument("power_of_two_sizes: n_min must be >= 1, got " + std::to_string(n_min));
  std::vector<int> sizes;
  for (long long n = 1; n <= n_max; n *= 2)
    if (n >= n_min) sizes.push_back(static_cast<int>(n));
  if (sizes.empty())
    throw std::invalid_argument("power_of_two_sizes: no power of two in [" + std::to_string(n_min) + ", " +
                                std::to_string(n_max) + "]");
  return sizes;
}

ReplicateError replicate_error(const Eigen::Ref<const Eigen::MatrixXd>& estimates,
                               const Eigen::Ref<const Eigen::VectorXd>& reference) {
  const Eigen::Index replicates = estimates.rows(), samples = estimates.cols();
  if (replicates < 2) throw std::invalid_argument("replicate_error: needs at least 2 replicates");
  if (samples < 1 || reference.size() != samples)
    throw std::invalid_argument("replicate_error: " + std::to_string(samples) + " estimated values against " +
                                std::to_string(reference.size()) + " reference values");
  if (!estimates.allFinite() || !reference.allFinite())
    throw std::invalid_argument("replicate_error: a value is not finite");
  const double count = static_cast<double>(replicates * samples);
  ReplicateError e;
  e.rms_error = std::sqrt((estimates.rowwise() - reference.transpose()).squaredNorm() / count);
  const Eigen::RowVectorXd replicate_mean = estimates.colwise().mean();
  e.spread = std::sqrt((estimates.rowwise() - replicate_mean).squaredNorm() /
                       (static_cast<double>(replicates - 1) * static_cast<double>(samples)));
  return e;
}

ReplicateError replicate_error(std::span<const double> estimates, double reference) {
  const Eigen::Map<const Eigen::MatrixXd> column(estimates.data(), static_cast<Eigen::Index>(estimates.size()), 1);
  return replicate_error(column, Eigen::VectorXd::Constant(1, reference));
}

double PowerLawFit::error_at(double n) const { return coefficient * std::pow(n, exponent); }

PowerLawFit fit_power_law(std::span<const double> n, std::span<const double> error) {
  if (n.size() != error.size())
    throw std::invalid_argument("fit_power_law: " + std::to_string(n.size()) + " sizes against " +
                                std::to_string(error.size()) + " errors");
  if (n.size() < 2) throw std::invalid_argument("fit_power_law: needs at least 2 points");
  const Eigen::Index points = static_cast<Eigen::Index>(n.size());
  Eigen::MatrixXd design(points, 2);
  Eigen::VectorXd log_error(points);
  for (Eigen::Index k = 0; k < points; ++k) {
    if (!(std::isfinite(n[k]) && n[k] > 0 && std::isfinite(error[k]) && error[k] > 0))
      throw std::invalid_argument("fit_power_law: N = " + std::to_string(n[k]) + ", error = " +
                                  std::to_string(error[k]) + ": both must be finite and positive");
    design(k, 0) = 1.0;
    design(k, 1) = std::log(n[k]);
    log_error(k) = std::log(error[k]);
  }
  const double log_n_min = design.col(1).minCoeff(), log_n_max = design.col(1).maxCoeff();
  if (log_n_min == log_n_max) throw std::invalid_argument("fit_power_law: all N are equal");

  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
  const Eigen::Vector2d beta = qr.solve(log_error);
  PowerLawFit fit;
  fit.coefficient = std::exp(beta(0));
  fit.exponent = beta(1);
  fit.points = static_cast<int>(points);
  fit.n_min = std::exp(log_n_min);
  fit.n_max = std::exp(log_n_max);
  if (points > 2) {
    const double residual_variance = (log_error - design * beta).squaredNorm() / static_cast<double>(points - 2);
    const Eigen::Matrix2d covariance = residual_variance * (design.transpose() * design).inverse();
    fit.exponent_se = std::sqrt(covariance(1, 1));
  }
  return fit;
}

RunsForError runs_for_error(const PowerLawFit& fit, std::span<const int> sizes, std::span<const double> errors,
                            double target) {
  if (!(target > 0)) throw std::invalid_argument("runs_for_error: the target error must be positive");
  if (sizes.empty() || sizes.size() != errors.size())
    throw std::invalid_argument("runs_for_error: " + std::to_string(sizes.size()) + " sizes against " +
                                std::to_string(errors.size()) + " errors");
  for (std::size_t k = 1; k < sizes.size(); ++k)
    if (sizes[k] <= sizes[k - 1]) throw std::invalid_argument("runs_for_error: the sizes must increase");

  RunsForError runs;
  runs.fitted = fit.exponent < 0 ? std::pow(target / fit.coefficient, 1.0 / fit.exponent)
                                 : std::numeric_limits<double>::infinity();
  runs.extrapolated = !(runs.fitted >= fit.n_min && runs.fitted <= fit.n_max);
  for (std::size_t k = sizes.size(); k-- > 0 && errors[k] <= target;) runs.observed = sizes[k];
  return runs;
}

}  // namespace rover::study
