// See least_squares_uncertainty.hpp.
#include "study/estimators/least_squares_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <Eigen/SVD>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/students_t.hpp>

namespace rover::study {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A central-difference Jacobian has relative errors ~ eps^(2/3) ~ 4e-11; the
// covariance amplifies them by about the condition number of the scaled J, so
// beyond 1e7 its leading digits are no longer trustworthy.
constexpr double kIllConditioned = 1e7;
constexpr double kStrongCorrelation = 0.99;

std::string parameter_name(const std::vector<std::string>& names, Eigen::Index j) {
  return names.empty() ? "parameter " + std::to_string(j) : names[static_cast<std::size_t>(j)];
}

// "a", "a and b", "a, b and c"
std::string join_names(const std::vector<std::string>& items) {
  std::string text;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i > 0) text += i + 1 == items.size() ? " and " : ", ";
    text += items[i];
  }
  return text;
}

void append(std::string& warning, const std::string& sentence) {
  if (!warning.empty()) warning += "; ";
  warning += sentence;
}

// The arguments' sizes and values (throws std::invalid_argument).
void check_arguments(const Eigen::VectorXd& parameters, const Eigen::VectorXd& residuals,
                     const Eigen::MatrixXd& jacobian, double confidence, const std::vector<std::string>& names) {
  const Eigen::Index n = residuals.size(), p = parameters.size();
  if (p < 1) throw std::invalid_argument("gauss_newton_uncertainty: no parameters");
  if (jacobian.rows() != n || jacobian.cols() != p)
    throw std::invalid_argument("gauss_newton_uncertainty: the Jacobian is " +
                                std::to_string(jacobian.rows()) + " x " + std::to_string(jacobian.cols()) +
                                ", expected " + std::to_string(n) + " residuals x " + std::to_string(p) +
                                " parameters");
  if (n <= p)
    throw std::invalid_argument("gauss_newton_uncertainty: " + std::to_string(n) + " residuals for " +
                                std::to_string(p) + " parameters leave no degrees of freedom for the noise");
  if (!names.empty() && static_cast<Eigen::Index>(names.size()) != p)
    throw std::invalid_argument("gauss_newton_uncertainty: " + std::to_string(names.size()) + " names for " +
                                std::to_string(p) + " parameters");
  if (!(confidence > 0.0 && confidence < 1.0))
    throw std::invalid_argument("gauss_newton_uncertainty: confidence must be in (0, 1)");
  if (!parameters.allFinite() || !residuals.allFinite() || !jacobian.allFinite())
    throw std::invalid_argument("gauss_newton_uncertainty: non-finite parameter, residual or Jacobian entry");
}

// The warnings of u.warning: a rank-deficient J (which parameters are
// confounded, which have no effect at all), an ill-conditioned J, and every
// strongly correlated pair.
void append_identifiability_warnings(LeastSquaresUncertainty& u, const std::vector<bool>& zero_column,
                                     const std::vector<std::string>& confounded,
                                     const std::vector<std::string>& names) {
  const auto p = static_cast<Eigen::Index>(zero_column.size());
  if (u.rank < p) {
    std::ostringstream text;
    text << "J is rank deficient (rank " << u.rank << " of " << p << "): ";
    std::vector<std::string> zero;
    for (Eigen::Index j = 0; j < p; ++j)
      if (zero_column[static_cast<std::size_t>(j)]) zero.push_back(parameter_name(names, j));
    if (confounded.size() == 1)
      text << confounded.front() << " is not identifiable from these data";
    else
      text << join_names(confounded) << " are not separately identifiable from these data";
    if (!zero.empty())
      text << " (" << join_names(zero) << (zero.size() == 1 ? " has" : " have")
           << " no effect on the residuals)";
    append(u.warning, text.str());
  } else if (u.condition_number > kIllConditioned) {
    std::ostringstream text;
    text << "J is ill-conditioned (condition number " << u.condition_number
         << " after column scaling): some parameter combination is barely identifiable";
    append(u.warning, text.str());
  }
  for (Eigen::Index i = 0; i < p; ++i)
    for (Eigen::Index j = i + 1; j < p; ++j)
      if (std::abs(u.correlation(i, j)) > kStrongCorrelation) {
        std::ostringstream text;
        text << parameter_name(names, i) << " and " << parameter_name(names, j)
             << " are strongly correlated (r = " << u.correlation(i, j) << ")";
        append(u.warning, text.str());
      }
}

}  // namespace

LeastSquaresUncertainty gauss_newton_uncertainty(const Eigen::VectorXd& parameters,
                                                 const Eigen::VectorXd& residuals,
                                                 const Eigen::MatrixXd& jacobian, double confidence,
                                                 const std::vector<std::string>& names) {
  check_arguments(parameters, residuals, jacobian, confidence, names);
  const Eigen::Index n = residuals.size(), p = parameters.size();

  // Column scaling: J = Js D with unit-norm columns of Js (a zero column stays zero).
  Eigen::VectorXd column_scale = jacobian.colwise().norm().transpose();
  std::vector<bool> zero_column(static_cast<std::size_t>(p));
  for (Eigen::Index j = 0; j < p; ++j) {
    zero_column[static_cast<std::size_t>(j)] = column_scale[j] == 0.0;
    if (column_scale[j] == 0.0) column_scale[j] = 1.0;
  }
  const Eigen::MatrixXd scaled = jacobian * column_scale.cwiseInverse().asDiagonal();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeFullV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  const Eigen::MatrixXd& v = svd.matrixV();
  const double rank_tolerance = static_cast<double>(std::max(n, p)) * kEps * sigma[0];
  Eigen::Index rank = 0;
  while (rank < p && sigma[rank] > rank_tolerance) ++rank;

  LeastSquaresUncertainty u;
  u.rank = static_cast<int>(rank);
  u.degrees_of_freedom = static_cast<int>(n - rank);
  u.noise_sd = std::sqrt(residuals.squaredNorm() / static_cast<double>(u.degrees_of_freedom));
  u.condition_number = rank == p ? sigma[0] / sigma[p - 1] : kInf;

  // Pseudo-inverse covariance on the identifiable subspace, unscaled.
  const Eigen::MatrixXd v_range = v.leftCols(rank);
  const Eigen::VectorXd inverse_sigma_squared = sigma.head(rank).array().square().inverse();
  const Eigen::MatrixXd scaled_covariance = v_range * inverse_sigma_squared.asDiagonal() * v_range.transpose();
  const Eigen::VectorXd inverse_scale = column_scale.cwiseInverse();
  u.covariance = u.noise_sd * u.noise_sd * inverse_scale.asDiagonal() * scaled_covariance *
                 inverse_scale.asDiagonal();

  // A parameter with a component in the null space of J is not identifiable.
  std::vector<bool> identifiable(static_cast<std::size_t>(p), true);
  std::vector<std::string> confounded;
  for (Eigen::Index j = 0; j < p; ++j)
    if (rank < p && v.row(j).tail(p - rank).norm() > std::sqrt(kEps)) {
      identifiable[static_cast<std::size_t>(j)] = false;
      confounded.push_back(parameter_name(names, j));
      u.covariance.row(j).setConstant(kNaN);
      u.covariance.col(j).setConstant(kNaN);
    }
  for (Eigen::Index j = 0; j < p; ++j)
    if (!identifiable[static_cast<std::size_t>(j)]) u.covariance(j, j) = kInf;

  const double t = boost::math::quantile(boost::math::students_t(u.degrees_of_freedom),
                                         0.5 * (1.0 + confidence));
  u.standard_error = u.covariance.diagonal().cwiseSqrt();
  u.lower = parameters - t * u.standard_error;
  u.upper = parameters + t * u.standard_error;
  u.correlation.resize(p, p);
  for (Eigen::Index i = 0; i < p; ++i)
    for (Eigen::Index j = 0; j < p; ++j) {
      const bool both = identifiable[static_cast<std::size_t>(i)] && identifiable[static_cast<std::size_t>(j)];
      const double denominator = u.standard_error[i] * u.standard_error[j];
      u.correlation(i, j) = i == j ? 1.0 : (both && denominator > 0.0 ? u.covariance(i, j) / denominator : kNaN);
    }

  append_identifiability_warnings(u, zero_column, confounded, names);
  return u;
}

std::vector<DifferenceStep> finite_difference_steps(const Eigen::VectorXd& x, const Eigen::VectorXd& lower,
                                                    const Eigen::VectorXd& upper,
                                                    const Eigen::VectorXd& typical) {
  const Eigen::Index p = x.size();
  if (lower.size() != p || upper.size() != p || typical.size() != p)
    throw std::invalid_argument("finite_difference_steps: x, lower, upper and typical differ in size");
  std::vector<DifferenceStep> steps(static_cast<std::size_t>(p));
  for (Eigen::Index j = 0; j < p; ++j) {
    const std::string at = " (parameter " + std::to_string(j) + ")";
    if (!(typical[j] > 0.0) || !std::isfinite(typical[j]))
      throw std::invalid_argument("finite_difference_steps: typical must be finite and > 0" + at);
    if (!(lower[j] < upper[j]))
      throw std::invalid_argument("finite_difference_steps: needs lower < upper" + at);
    if (!(x[j] >= lower[j] && x[j] <= upper[j]) || !std::isfinite(x[j]))
      throw std::invalid_argument("finite_difference_steps: x outside [lower, upper]" + at);
    const double scale = std::max(std::abs(x[j]), typical[j]);
    const double central_step = std::cbrt(kEps) * scale;
    const double forward_step = std::sqrt(kEps) * scale;
    const double room_below = x[j] - lower[j], room_above = upper[j] - x[j];
    const double room = std::min(room_below, room_above);
    DifferenceStep& s = steps[static_cast<std::size_t>(j)];
    if (room >= forward_step) {
      s = {std::min(central_step, room), DifferenceScheme::central};
    } else if (room_above >= room_below) {
      s = {std::min(forward_step, room_above), DifferenceScheme::one_sided};
    } else {
      s = {-std::min(forward_step, room_below), DifferenceScheme::one_sided};
    }
  }
  return steps;
}

Eigen::VectorXd central_difference_steps(const Eigen::VectorXd& x, const Eigen::VectorXd& lower,
                                         const Eigen::VectorXd& upper, const Eigen::VectorXd& typical) {
  const std::vector<DifferenceStep> steps = finite_difference_steps(x, lower, upper, typical);
  Eigen::VectorXd h(x.size());
  for (Eigen::Index j = 0; j < x.size(); ++j) h[j] = steps[static_cast<std::size_t>(j)].step;
  return h;
}

ProfileInterval profile_likelihood_interval(const std::vector<double>& values, const std::vector<double>& rss,
                                            double noise_variance, double confidence) {
  const std::size_t n = values.size();
  if (n < 2 || rss.size() != n)
    throw std::invalid_argument("profile_likelihood_interval: needs at least 2 values and one rss per value");
  if (!(noise_variance > 0.0) || !std::isfinite(noise_variance))
    throw std::invalid_argument("profile_likelihood_interval: noise_variance must be finite and > 0");
  if (!(confidence > 0.0 && confidence < 1.0))
    throw std::invalid_argument("profile_likelihood_interval: confidence must be in (0, 1)");
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(values[i]) || !std::isfinite(rss[i]))
      throw std::invalid_argument("profile_likelihood_interval: non-finite value or rss at point " +
                                  std::to_string(i));
    if (i > 0 && !(values[i] > values[i - 1]))
      throw std::invalid_argument("profile_likelihood_interval: values must be strictly ascending");
  }

  const auto best_index = static_cast<std::size_t>(std::min_element(rss.begin(), rss.end()) - rss.begin());
  ProfileInterval interval;
  interval.best = values[best_index];
  double rss_min = rss[best_index];
  if (best_index > 0 && best_index + 1 < n) {
    // Vertex of the parabola through the minimum and its neighbours (Newton form).
    const double x0 = values[best_index - 1], x1 = values[best_index], x2 = values[best_index + 1];
    const double y0 = rss[best_index - 1], y1 = rss[best_index], y2 = rss[best_index + 1];
    const double slope01 = (y1 - y0) / (x1 - x0);
    const double curvature = ((y2 - y1) / (x2 - x1) - slope01) / (x2 - x0);
    if (curvature > 0.0) {
      const double vertex = std::clamp(0.5 * (x0 + x1) - slope01 / (2.0 * curvature), x0, x2);
      interval.best = vertex;
      rss_min = std::min(rss_min, y0 + slope01 * (vertex - x0) + curvature * (vertex - x0) * (vertex - x1));
    }
  }

  const double threshold = boost::math::quantile(boost::math::chi_squared(1.0), confidence);
  const auto deviance = [&](std::size_t i) { return (rss[i] - rss_min) / noise_variance; };
  // The crossing of the threshold between grid points `inside` and `outside`.
  const auto crossing = [&](std::size_t inside, std::size_t outside) {
    const double d_in = deviance(inside), d_out = deviance(outside);
    return values[inside] + (threshold - d_in) / (d_out - d_in) * (values[outside] - values[inside]);
  };

  std::size_t i = best_index;
  while (i > 0 && deviance(i - 1) <= threshold) --i;
  interval.lower_open = i == 0;
  interval.lower = interval.lower_open ? -kInf : crossing(i, i - 1);
  i = best_index;
  while (i + 1 < n && deviance(i + 1) <= threshold) ++i;
  interval.upper_open = i + 1 == n;
  interval.upper = interval.upper_open ? kInf : crossing(i, i + 1);
  interval.identifiable = !(interval.lower_open && interval.upper_open);
  return interval;
}

}  // namespace rover::study
