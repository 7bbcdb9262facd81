#include "study/estimators/band_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rover::study {

double quantile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) throw std::invalid_argument("quantile of an empty sample");
  const double h = (static_cast<double>(sorted.size()) - 1.0) * p;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

Band band_statistics(const Eigen::MatrixXd& curves) {
  std::vector<Eigen::Index> rows;
  for (Eigen::Index r = 0; r < curves.rows(); ++r)
    if (curves.row(r).allFinite()) rows.push_back(r);
  Band band;
  band.samples_used = static_cast<int>(rows.size());
  const auto T = static_cast<std::size_t>(curves.cols());
  const double nan = std::nan("");
  for (auto* v : {&band.mean, &band.std, &band.lower, &band.upper, &band.p00135, &band.p99865})
    v->assign(T, nan);
  if (rows.empty()) return band;
  std::vector<double> column(rows.size());
  const double n = static_cast<double>(rows.size());
  for (std::size_t t = 0; t < T; ++t) {
    // Shifted by the first value: exact for identical samples, and no
    // cancellation for curves far from zero.
    for (std::size_t k = 0; k < rows.size(); ++k) column[k] = curves(rows[k], static_cast<Eigen::Index>(t));
    double shifted_sum = 0.0;
    for (double x : column) shifted_sum += x - column[0];
    const double mean = column[0] + shifted_sum / n;
    double ss = 0.0;
    for (double x : column) ss += (x - mean) * (x - mean);
    const double sd = rows.size() > 1 ? std::sqrt(ss / (n - 1.0)) : nan;  // one curve has no spread to measure
    std::sort(column.begin(), column.end());
    band.mean[t] = mean;
    band.std[t] = sd;
    band.lower[t] = mean - 3.0 * sd;
    band.upper[t] = mean + 3.0 * sd;
    band.p00135[t] = quantile(column, 0.00135);
    band.p99865[t] = quantile(column, 0.99865);
  }
  return band;
}

}  // namespace rover::study
