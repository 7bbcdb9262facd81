#include "core/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rover {
namespace {

void check_curve(const std::vector<double>& t, const std::vector<double>& y, const char* name) {
  if (t.size() != y.size() || t.size() < 2)
    throw std::invalid_argument(std::string(name) + ": need at least 2 samples with equal t and y sizes");
  for (std::size_t i = 1; i < t.size(); ++i)
    if (!(t[i] > t[i - 1]))
      throw std::invalid_argument(std::string(name) + ": sample times must increase (index " +
                                  std::to_string(i) + ")");
}

}  // namespace

double interpolate(const std::vector<double>& t, const std::vector<double>& y, double at) {
  if (t.empty() || y.size() != t.size())
    throw std::invalid_argument("a curve without samples (a run that failed before its first output) cannot be "
                                "compared");
  if (at <= t.front()) return y.front();
  if (at >= t.back()) return y.back();
  const auto it = std::upper_bound(t.begin(), t.end(), at);
  const std::size_t i = static_cast<std::size_t>(it - t.begin());
  const double w = (at - t[i - 1]) / (t[i] - t[i - 1]);
  return (1.0 - w) * y[i - 1] + w * y[i];
}

double rms_difference(const std::vector<double>& t_a, const std::vector<double>& a,
                      const std::vector<double>& t_b, const std::vector<double>& b) {
  check_curve(t_a, a, "first curve");
  check_curve(t_b, b, "second curve");
  const double lo = std::max(t_a.front(), t_b.front()), hi = std::min(t_a.back(), t_b.back());
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < t_a.size(); ++i) {
    if (t_a[i] < lo - 1e-12 || t_a[i] > hi + 1e-12) continue;
    const double d = interpolate(t_b, b, t_a[i]) - a[i];
    sum += d * d;
    ++n;
  }
  if (n == 0) throw std::invalid_argument("the two curves have no common time interval");
  return std::sqrt(sum / static_cast<double>(n));
}

double deflection_error(const std::vector<double>& t, const std::vector<double>& z,
                        const std::vector<double>& t_ref, const std::vector<double>& z_ref,
                        double t_rest_s) {
  check_curve(t, z, "curve");
  check_curve(t_ref, z_ref, "reference curve");
  const double z_min = *std::min_element(z.begin(), z.end());
  const double z_min_ref = *std::min_element(z_ref.begin(), z_ref.end());
  return (interpolate(t, z, t_rest_s) - z_min) / (interpolate(t_ref, z_ref, t_rest_s) - z_min_ref) - 1.0;
}

double at_rest_error(const std::vector<double>& t, const std::vector<double>& z,
                     const std::vector<double>& t_ref, const std::vector<double>& z_ref,
                     double t_rest_s) {
  check_curve(t, z, "curve");
  check_curve(t_ref, z_ref, "reference curve");
  return interpolate(t, z, t_rest_s) / interpolate(t_ref, z_ref, t_rest_s) - 1.0;
}

}  // namespace rover
