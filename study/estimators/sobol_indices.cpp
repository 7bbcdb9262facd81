#include "study/estimators/sobol_indices.hpp"
#include "study/estimators/work_stopped.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <boost/math/distributions/normal.hpp>
#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_int_distribution.hpp>

#include "study/estimators/band_statistics.hpp"

namespace rover::study {

int PickFreezeLayout::runs_per_group() const {
  return second_order ? 2 * dimensions + 2 : dimensions + 2;
}

int PickFreezeLayout::total_runs() const { return base_samples * runs_per_group(); }

DesignMatrix pick_freeze_design(const DesignMatrix& A, const DesignMatrix& B, bool second_order) {
  if (A.rows() != B.rows() || A.cols() != B.cols())
    throw std::invalid_argument("pick_freeze_design: A is " + std::to_string(A.rows()) + " x " +
                                std::to_string(A.cols()) + " but B is " +
                                std::to_string(B.rows()) + " x " + std::to_string(B.cols()));
  if (A.rows() == 0 || A.cols() == 0)
    throw std::invalid_argument("pick_freeze_design: A and B must have at least one row and column");
  const PickFreezeLayout layout{static_cast<int>(A.rows()), static_cast<int>(A.cols()),
                                second_order};
  const int d = layout.dimensions, per_group = layout.runs_per_group();
  DesignMatrix design(layout.total_runs(), d);
  for (int g = 0; g < layout.base_samples; ++g) {
    const int first = g * per_group;
    design.row(first) = A.row(g);
    design.row(first + 1) = B.row(g);
    for (int i = 0; i < d; ++i) {
      design.row(first + 2 + i) = A.row(g);
      design(first + 2 + i, i) = B(g, i);
      if (second_order) {
        design.row(first + 2 + d + i) = B.row(g);
        design(first + 2 + d + i, i) = A(g, i);
      }
    }
  }
  return design;
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kEps = std::numeric_limits<double>::epsilon();

// Every estimator above is a function of sums over the groups of a few per-group
// products. One row of the term matrix holds them for one group, so a bootstrap
// resample is a weighted column sum (weights: how often each group is drawn) and
// a jackknife replicate is the total minus one row.
struct TermColumns {
  int d = 0;
  bool second_order = false;
  static constexpr int kA = 0, kB = 1, kAA = 2, kBB = 3, kAB = 4, kPerInputStart = 5;
  static constexpr int kPerInput = 7;
  // Per input i (y_i = f(A_B^i), delta_i = y_i - f(A)):
  int y(int i) const { return kPerInputStart + kPerInput * i; }
  int yy(int i) const { return y(i) + 1; }
  int a_y(int i) const { return y(i) + 2; }
  int b_y(int i) const { return y(i) + 3; }
  int delta(int i) const { return y(i) + 4; }
  int b_delta(int i) const { return y(i) + 5; }
  int delta_delta(int i) const { return y(i) + 6; }
  // Second order, per input i (z_i = f(B_A^i)) and per pair i < j.
  int second_start() const { return kPerInputStart + kPerInput * d; }
  int z(int i) const { return second_start() + 2 * i; }
  int zz(int i) const { return z(i) + 1; }
  int pairs() const { return second_order ? d * (d - 1) / 2 : 0; }
  int pair(int i, int j) const { return i * (2 * d - i - 1) / 2 + (j - i - 1); }  // i < j
  int z_y(int i, int j) const { return second_start() + 2 * d + 2 * pair(i, j); }
  int z_y_minus_ab(int i, int j) const { return z_y(i, j) + 1; }
  int count() const { return second_start() + (second_order ? 2 * d + 2 * pairs() : 0); }
  // Estimates: S1 (d), ST (d), S2 (pairs, in pair order).
  int estimates() const { return 2 * d + pairs(); }
};

// Term matrix (groups x terms) of the outputs `y` (already centred), one row per group in `groups`.
Eigen::MatrixXd term_matrix(const PickFreezeLayout& layout, const TermColumns& c,
                            const Eigen::Ref<const Eigen::VectorXd>& y,
                            const std::vector<int>& groups) {
  const int d = layout.dimensions, per_group = layout.runs_per_group();
  Eigen::MatrixXd terms(static_cast<Eigen::Index>(groups.size()), c.count());
  for (Eigen::Index row = 0; row < terms.rows(); ++row) {
    const double* run = y.data() + static_cast<Eigen::Index>(groups[row]) * per_group;
    const double a = run[0], b = run[1];
    terms(row, c.kA) = a;
    terms(row, c.kB) = b;
    terms(row, c.kAA) = a * a;
    terms(row, c.kBB) = b * b;
    terms(row, c.kAB) = a * b;
    for (int i = 0; i < d; ++i) {
      const double yi = run[2 + i], delta = yi - a;
      terms(row, c.y(i)) = yi;
      terms(row, c.yy(i)) = yi * yi;
      terms(row, c.a_y(i)) = a * yi;
      terms(row, c.b_y(i)) = b * yi;
      terms(row, c.delta(i)) = delta;
      terms(row, c.b_delta(i)) = b * delta;
      terms(row, c.delta_delta(i)) = delta * delta;
    }
    if (!c.second_order) continue;
    for (int i = 0; i < d; ++i) {
      const double zi = run[2 + d + i];
      terms(row, c.z(i)) = zi;
      terms(row, c.zz(i)) = zi * zi;
      for (int j = i + 1; j < d; ++j) {
        terms(row, c.z_y(i, j)) = zi * run[2 + j];
        terms(row, c.z_y_minus_ab(i, j)) = zi * run[2 + j] - a * b;
      }
    }
  }
  return terms;
}

// Pearson correlation from the sums of x, y, x^2, y^2, xy over n groups.
double correlation(double sx, double sy, double sxx, double syy, double sxy, double n) {
  const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n;
  if (!(vx > 0.0 && vy > 0.0)) return kNaN;
  return (sxy - sx * sy / n) / std::sqrt(vx * vy);
}

// Mean and unbiased variance of the 2n A and B outputs from the sums.
void mean_and_variance(const TermColumns& c, const double* s, double n, double& mean,
                       double& variance) {
  mean = (s[c.kA] + s[c.kB]) / (2.0 * n);
  variance = (s[c.kAA] + s[c.kBB] - 2.0 * n * mean * mean) / (2.0 * n - 1.0);
}

// The estimates (S1, ST, S2 in TermColumns order) from the sums `s` over n groups.
// No allocation: this runs once per bootstrap and jackknife replicate.
void estimates_from_sums(const TermColumns& c, SobolEstimator estimator, const double* s,
                         double n, double* out) {
  double mean = 0, variance = 0;
  mean_and_variance(c, s, n, mean, variance);
  const int d = c.d;
  double* S1 = out;
  double* ST = out + d;
  double* S2 = out + 2 * d;
  if (!(variance > 0.0)) {
    std::fill(out, out + c.estimates(), kNaN);
    return;
  }
  if (estimator == SobolEstimator::kSaltelliJansen) {
    for (int i = 0; i < d; ++i) {
      // Sum of (f(B) - f0) (f(A_B^i) - f(A)): the centring subtracts f0 * sum(delta_i).
      S1[i] = (s[c.b_delta(i)] - mean * s[c.delta(i)]) / n / variance;
      ST[i] = s[c.delta_delta(i)] / (2.0 * n) / variance;
    }
    for (int i = 0; i < d && c.second_order; ++i)
      for (int j = i + 1; j < d; ++j) {
        // Sum of (f(B_A^i) - f0)(f(A_B^j) - f0) - (f(A) - f0)(f(B) - f0).
        const double closed =
            (s[c.z_y_minus_ab(i, j)] - mean * (s[c.z(i)] + s[c.y(j)] - s[c.kA] - s[c.kB])) / n;
        S2[c.pair(i, j)] = closed / variance - S1[i] - S1[j];
      }
    return;
  }
  for (int i = 0; i < d; ++i) {
    S1[i] = correlation(s[c.kB], s[c.y(i)], s[c.kBB], s[c.yy(i)], s[c.b_y(i)], n);
    ST[i] = 1.0 - correlation(s[c.kA], s[c.y(i)], s[c.kAA], s[c.yy(i)], s[c.a_y(i)], n);
  }
  for (int i = 0; i < d && c.second_order; ++i)
    for (int j = i + 1; j < d; ++j) {
      const double closed = correlation(s[c.z(i)], s[c.y(j)], s[c.zz(i)], s[c.yy(j)],
                                        s[c.z_y(i, j)], n);
      S2[c.pair(i, j)] = closed - S1[i] - S1[j];
    }
}

// A variance at rounding level of outputs of magnitude `scale` counts as zero.
bool variance_is_zero(double variance, double scale) {
  const double rounding = 16.0 * kEps * scale;
  return !(variance > rounding * rounding);
}

void check_layout(const PickFreezeLayout& layout, Eigen::Index rows) {
  if (layout.base_samples < 1 || layout.dimensions < 1)
    throw std::invalid_argument("Sobol' indices: the layout needs base_samples >= 1 and "
                                "dimensions >= 1 (got " + std::to_string(layout.base_samples) +
                                " and " + std::to_string(layout.dimensions) + ")");
  if (rows != layout.total_runs())
    throw std::invalid_argument("Sobol' indices: " + std::to_string(rows) +
                                " outputs for a layout of " + std::to_string(layout.total_runs()) +
                                " runs (" + std::to_string(layout.base_samples) + " groups of " +
                                std::to_string(layout.runs_per_group()) + ")");
}

void check_enough_groups(int used, int total) {
  if (used < kMinCompleteSobolGroups)
    throw std::invalid_argument("Sobol' indices: only " + std::to_string(used) + " of " + std::to_string(total) +
                                " groups have no failed (non-finite) run; at least " +
                                std::to_string(kMinCompleteSobolGroups) + " complete groups are needed");
}

// Confidence interval of one estimate from its bootstrap replicates (sorted
// in place; non-finite replicates are left out) and, for BCa, its jackknife
// replicates.
void bootstrap_interval(double estimate, std::vector<double>& replicates,
                        const std::vector<double>& jackknife, double confidence,
                        BootstrapInterval method, double& lower, double& upper) {
  lower = upper = kNaN;
  replicates.erase(std::remove_if(replicates.begin(), replicates.end(),
                                  [](double v) { return !std::isfinite(v); }),
                   replicates.end());
  if (replicates.size() < 2 || !std::isfinite(estimate)) return;
  std::sort(replicates.begin(), replicates.end());
  // All replicates equal up to rounding (an index that is exactly 0 or 1 by
  // construction): the interval is the point.
  if (replicates.back() - replicates.front() <= 64.0 * kEps) {
    lower = std::min(estimate, replicates.front());
    upper = std::max(estimate, replicates.back());
    return;
  }
  const double tail = 0.5 * (1.0 - confidence);
  double p_lower = tail, p_upper = 1.0 - tail;
  if (method == BootstrapInterval::kBca) {
    const boost::math::normal standard_normal;
    const auto R = static_cast<double>(replicates.size());
    const auto below = std::lower_bound(replicates.begin(), replicates.end(), estimate);
    const auto not_above = std::upper_bound(replicates.begin(), replicates.end(), estimate);
    double fraction_below = (static_cast<double>(below - replicates.begin()) +
                             0.5 * static_cast<double>(not_above - below)) / R;
    fraction_below = std::clamp(fraction_below, 0.5 / R, 1.0 - 0.5 / R);
    const double z0 = boost::math::quantile(standard_normal, fraction_below);
    double mean = 0.0;
    int finite = 0;
    for (double v : jackknife)
      if (std::isfinite(v)) mean += v, ++finite;
    mean /= std::max(finite, 1);
    double sum2 = 0.0, sum3 = 0.0;
    for (double v : jackknife)
      if (std::isfinite(v)) {
        const double u = mean - v;
        sum2 += u * u;
        sum3 += u * u * u;
      }
    const double acceleration = sum2 > 0.0 ? sum3 / (6.0 * std::pow(sum2, 1.5)) : 0.0;
    bool valid = true;
    auto adjusted = [&](double p) {
      const double z = z0 + boost::math::quantile(standard_normal, p);
      const double denominator = 1.0 - acceleration * z;
      if (!(denominator > 0.0)) valid = false;
      return valid ? boost::math::cdf(standard_normal, z0 + z / denominator) : p;
    };
    const double a_lower = adjusted(p_lower), a_upper = adjusted(p_upper);
    if (valid) p_lower = a_lower, p_upper = a_upper;
  }
  lower = quantile(replicates, p_lower);
  upper = quantile(replicates, p_upper);
}

// The bootstrap intervals of every estimate (resampling the groups' term
// rows), with the jackknife the BCa interval needs; `point` holds the
// estimates themselves.
void bootstrap_intervals(const TermColumns& columns, const SobolOptions& options, const Eigen::MatrixXd& terms,
                         const Eigen::VectorXd& totals, double n, const Eigen::VectorXd& point,
                         Eigen::VectorXd& lower, Eigen::VectorXd& upper) {
  const int estimates = columns.estimates();
  const int R = options.bootstrap_resamples;
  // Bootstrap: replicates(e, r) is estimate e on resample r.
  Eigen::MatrixXd replicates(estimates, R);
  Eigen::VectorXd counts(terms.rows()), sums(terms.cols());
  boost::random::mt19937_64 engine(options.seed);
  boost::random::uniform_int_distribution<Eigen::Index> draw(0, terms.rows() - 1);
  for (int r = 0; r < R; ++r) {
    stop_if_requested(options.stop, "Sobol' indices: bootstrap");
    counts.setZero();
    for (Eigen::Index k = 0; k < terms.rows(); ++k) counts[draw(engine)] += 1.0;
    sums.noalias() = terms.transpose() * counts;
    estimates_from_sums(columns, options.estimator, sums.data(), n, replicates.col(r).data());
  }
  // Jackknife (leave one group out), for the BCa acceleration.
  Eigen::MatrixXd jackknife;
  if (options.interval == BootstrapInterval::kBca) {
    jackknife.resize(estimates, terms.rows());
    for (Eigen::Index g = 0; g < terms.rows(); ++g) {
      sums = totals - terms.row(g).transpose();
      estimates_from_sums(columns, options.estimator, sums.data(), n - 1.0,
                          jackknife.col(g).data());
    }
  }
  std::vector<double> values(static_cast<std::size_t>(R)), leave_one_out;
  for (int e = 0; e < estimates; ++e) {
    stop_if_requested(options.stop, "Sobol' indices: bootstrap intervals");
    const Eigen::VectorXd row = replicates.row(e).transpose();
    values.assign(row.data(), row.data() + R);
    if (jackknife.size() > 0) {
      const Eigen::VectorXd jack = jackknife.row(e).transpose();
      leave_one_out.assign(jack.data(), jack.data() + jack.size());
    }
    bootstrap_interval(point[e], values, leave_one_out, options.confidence, options.interval,
                       lower[e], upper[e]);
  }
}

}  // namespace

SobolIndices estimate_sobol_indices(const PickFreezeLayout& layout, const Eigen::VectorXd& y,
                                    const SobolOptions& options) {
  check_layout(layout, y.size());
  if (options.bootstrap_resamples < 0)
    throw std::invalid_argument("Sobol' indices: bootstrap_resamples must be >= 0");
  if (!(options.confidence > 0.0 && options.confidence < 1.0))
    throw std::invalid_argument("Sobol' indices: confidence must lie in (0, 1), got " +
                                std::to_string(options.confidence));
  const int d = layout.dimensions, per_group = layout.runs_per_group();
  SobolIndices result;
  result.groups_total = layout.base_samples;
  std::vector<int> groups;
  for (int g = 0; g < layout.base_samples; ++g) {
    if (y.segment(static_cast<Eigen::Index>(g) * per_group, per_group).allFinite())
      groups.push_back(g);
    else
      result.dropped_groups.push_back(g);
  }
  result.groups_used = static_cast<int>(groups.size());
  check_enough_groups(result.groups_used, result.groups_total);

  // Centre on the mean of the A and B runs used.
  double centre = 0.0, scale = 0.0;
  for (int g : groups)
    for (int k = 0; k < 2; ++k) {
      const double v = y[static_cast<Eigen::Index>(g) * per_group + k];
      centre += v;
      scale = std::max(scale, std::abs(v));
    }
  centre /= 2.0 * result.groups_used;
  const Eigen::VectorXd centred = y.array() - centre;

  const TermColumns columns{d, layout.second_order};
  const Eigen::MatrixXd terms = term_matrix(layout, columns, centred, groups);
  const Eigen::VectorXd totals = terms.colwise().sum().transpose();
  const double n = result.groups_used;
  double mean_centred = 0.0;
  mean_and_variance(columns, totals.data(), n, mean_centred, result.variance);
  result.mean = centre + mean_centred;
  if (variance_is_zero(result.variance, scale))
    throw std::invalid_argument("Sobol' indices: the output variance is zero (variance " +
                                std::to_string(result.variance) + " over the " +
                                std::to_string(2 * result.groups_used) +
                                " A and B runs); the indices are undefined");

  const int estimates = columns.estimates();
  Eigen::VectorXd point(estimates);
  estimates_from_sums(columns, options.estimator, totals.data(), n, point.data());

  Eigen::VectorXd lower = Eigen::VectorXd::Constant(estimates, kNaN);
  Eigen::VectorXd upper = lower;
  result.has_intervals = options.bootstrap_resamples > 0 && result.groups_used >= kMinBootstrapSobolGroups;
  if (result.has_intervals) bootstrap_intervals(columns, options, terms, totals, n, point, lower, upper);

  result.S1 = point.head(d);
  result.ST = point.segment(d, d);
  result.S1_lower = lower.head(d);
  result.S1_upper = upper.head(d);
  result.ST_lower = lower.segment(d, d);
  result.ST_upper = upper.segment(d, d);
  if (layout.second_order) {
    result.S2 = result.S2_lower = result.S2_upper = Eigen::MatrixXd::Constant(d, d, kNaN);
    for (int i = 0; i < d; ++i)
      for (int j = i + 1; j < d; ++j) {
        const int e = 2 * d + columns.pair(i, j);
        result.S2(i, j) = point[e];
        result.S2_lower(i, j) = lower[e];
        result.S2_upper(i, j) = upper[e];
      }
  }
  return result;
}

SobolIndicesAlongTime estimate_sobol_indices_along_time(const PickFreezeLayout& layout,
                                                        const Eigen::MatrixXd& Y,
                                                        SobolEstimator estimator) {
  check_layout(layout, Y.rows());
  const int d = layout.dimensions, per_group = layout.runs_per_group();
  const auto T = Y.cols();
  std::vector<int> groups;
  for (int g = 0; g < layout.base_samples; ++g)
    if (Y.middleRows(static_cast<Eigen::Index>(g) * per_group, per_group).allFinite())
      groups.push_back(g);
  SobolIndicesAlongTime result;
  result.groups_used = static_cast<int>(groups.size());
  check_enough_groups(result.groups_used, layout.base_samples);

  // First and total order only: the B_A^(i) runs of a second-order layout are not needed.
  const TermColumns columns{d, false};
  const double n = result.groups_used;
  result.S1 = result.ST = Eigen::MatrixXd::Constant(d, T, kNaN);
  result.variance.resize(T);
  Eigen::VectorXd column(Y.rows()), estimates(columns.estimates());
  for (Eigen::Index t = 0; t < T; ++t) {
    double centre = 0.0, scale = 0.0;
    for (int g : groups)
      for (int k = 0; k < 2; ++k) {
        const double v = Y(static_cast<Eigen::Index>(g) * per_group + k, t);
        centre += v;
        scale = std::max(scale, std::abs(v));
      }
    centre /= 2.0 * n;
    column = Y.col(t).array() - centre;
    const Eigen::VectorXd totals =
        term_matrix(layout, columns, column, groups).colwise().sum().transpose();
    double mean = 0.0;
    mean_and_variance(columns, totals.data(), n, mean, result.variance[t]);
    if (variance_is_zero(result.variance[t], scale)) {
      result.variance[t] = 0.0;
      continue;
    }
    estimates_from_sums(columns, estimator, totals.data(), n, estimates.data());
    result.S1.col(t) = estimates.head(d);
    result.ST.col(t) = estimates.segment(d, d);
  }
  // Variance-weighted aggregates over the time samples with a defined index.
  result.aggregated_S1 = result.aggregated_ST = Eigen::VectorXd::Constant(d, kNaN);
  for (int i = 0; i < d; ++i) {
    double weight = 0.0, s1 = 0.0, st = 0.0;
    for (Eigen::Index t = 0; t < T; ++t) {
      if (result.variance[t] == 0.0 || !std::isfinite(result.S1(i, t)) ||
          !std::isfinite(result.ST(i, t)))
        continue;
      weight += result.variance[t];
      s1 += result.variance[t] * result.S1(i, t);
      st += result.variance[t] * result.ST(i, t);
    }
    if (weight > 0.0) {
      result.aggregated_S1[i] = s1 / weight;
      result.aggregated_ST[i] = st / weight;
    }
  }
  return result;
}

long long undefined_time_count(const SobolIndicesAlongTime& indices) {
  long long count = 0;
  for (Eigen::Index k = 0; k < indices.S1.cols(); ++k) count += indices.S1.col(k).allFinite() ? 0 : 1;
  return count;
}

}  // namespace rover::study
