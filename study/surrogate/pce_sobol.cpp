// See pce_sobol.hpp.
#include "study/surrogate/pce_sobol.hpp"
#include "study/estimators/work_stopped.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "study/estimators/splitmix64.hpp"

namespace rover::study {
namespace {

constexpr int kMinResamples = 2;
constexpr int kMaxResamples = 1000000;
// A variance at or below this fraction of the squared mean is zero up to rounding.
constexpr double kZeroVarianceRelative = 1e-28;
// Distinct constants folded into the resampling hash.
constexpr std::uint64_t kResampleStream = 0x5CE5A3B1D00Dull;

// The inputs of a term with a nonzero degree.
std::vector<int> support(const MultiIndex& alpha) {
  std::vector<int> s;
  for (std::size_t i = 0; i < alpha.size(); ++i)
    if (alpha[i] > 0) s.push_back(static_cast<int>(i));
  return s;
}

// Linear interpolation between order statistics (type 7 of Hyndman & Fan 1996).
double percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  const double h = p * static_cast<double>(values.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (h - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

void check_bootstrap(const PolynomialChaosExpansion& e, const DesignMatrix& x,
                     const Eigen::VectorXd& y, const PceBootstrapSettings& s) {
  if (s.resamples < kMinResamples || s.resamples > kMaxResamples)
    throw std::invalid_argument("PCE bootstrap: resamples " + std::to_string(s.resamples) +
                                " is outside [" + std::to_string(kMinResamples) + ", " +
                                std::to_string(kMaxResamples) + "]");
  if (!(s.confidence > 0.0 && s.confidence < 1.0)) {
    std::ostringstream text;
    text << "PCE bootstrap: confidence " << s.confidence << " is outside (0, 1)";
    throw std::invalid_argument(text.str());
  }
  if (x.rows() != y.size() || x.cols() != static_cast<Eigen::Index>(e.inputs.size()))
    throw std::invalid_argument("PCE bootstrap: the design is " + std::to_string(x.rows()) +
                                " x " + std::to_string(x.cols()) + " for " +
                                std::to_string(y.size()) + " outputs and " +
                                std::to_string(e.inputs.size()) + " inputs");
  if (!y.allFinite()) throw std::invalid_argument("PCE bootstrap: non-finite output value");
  if (e.constant_output)
    throw std::invalid_argument("PCE bootstrap: output '" + e.output_name +
                                "' is constant; its indices are undefined");
}

// Replicates of every index, one vector per index, laid out as
// mean, variance, S1 (d), ST (d), S2 (d x d row-major).
struct Replicates {
  int d = 0;
  std::vector<std::vector<double>> values;
  explicit Replicates(int dims) : d(dims), values(2 + 2 * dims + dims * dims) {}
  void add(const PceSobolIndices& s) {
    values[0].push_back(s.mean);
    values[1].push_back(s.variance);
    for (int i = 0; i < d; ++i) {
      values[2 + i].push_back(s.S1(i));
      values[2 + d + i].push_back(s.ST(i));
      for (int j = 0; j < d; ++j) values[2 + 2 * d + i * d + j].push_back(s.S2(i, j));
    }
  }
};

PceSobolIntervals intervals_from(const Replicates& r, double confidence) {
  const double lo = (1.0 - confidence) / 2.0, hi = 1.0 - lo;
  const int d = r.d;
  PceSobolIntervals out;
  out.confidence = confidence;
  out.mean_lower = percentile(r.values[0], lo);
  out.mean_upper = percentile(r.values[0], hi);
  out.variance_lower = percentile(r.values[1], lo);
  out.variance_upper = percentile(r.values[1], hi);
  out.S1_lower.resize(d), out.S1_upper.resize(d), out.ST_lower.resize(d), out.ST_upper.resize(d);
  out.S2_lower = Eigen::MatrixXd::Zero(d, d);
  out.S2_upper = Eigen::MatrixXd::Zero(d, d);
  for (int i = 0; i < d; ++i) {
    out.S1_lower(i) = percentile(r.values[2 + i], lo);
    out.S1_upper(i) = percentile(r.values[2 + i], hi);
    out.ST_lower(i) = percentile(r.values[2 + d + i], lo);
    out.ST_upper(i) = percentile(r.values[2 + d + i], hi);
    for (int j = i + 1; j < d; ++j) {
      out.S2_lower(i, j) = percentile(r.values[2 + 2 * d + i * d + j], lo);
      out.S2_upper(i, j) = percentile(r.values[2 + 2 * d + i * d + j], hi);
    }
  }
  return out;
}

}  // namespace

PceSobolIndices pce_sobol_indices(const std::vector<MultiIndex>& multi_indices,
                                  const Eigen::VectorXd& coefficients) {
  PceSobolIndices s;
  const int d = multi_indices.empty() ? 0 : static_cast<int>(multi_indices[0].size());
  Eigen::VectorXd v1 = Eigen::VectorXd::Zero(d), vt = Eigen::VectorXd::Zero(d);
  Eigen::MatrixXd v2 = Eigen::MatrixXd::Zero(d, d);
  for (std::size_t k = 0; k < multi_indices.size(); ++k) {
    const std::vector<int> sup = support(multi_indices[k]);
    const double c2 = coefficients(static_cast<Eigen::Index>(k)) *
                      coefficients(static_cast<Eigen::Index>(k));
    if (sup.empty()) {
      s.mean += coefficients(static_cast<Eigen::Index>(k));
      continue;
    }
    s.variance += c2;
    for (const int i : sup) vt(i) += c2;
    if (sup.size() == 1) v1(sup[0]) += c2;
    if (sup.size() == 2) v2(sup[0], sup[1]) += c2;
  }
  if (!(s.variance > kZeroVarianceRelative * s.mean * s.mean) || !std::isfinite(s.variance)) {
    s.undefined_reason = "the expansion's variance is zero: the output does not vary";
    return s;
  }
  s.defined = true;
  s.S1 = v1 / s.variance;
  s.ST = vt / s.variance;
  s.S2 = v2 / s.variance;
  s.S2_closed = Eigen::MatrixXd::Zero(d, d);
  for (int i = 0; i < d; ++i)
    for (int j = i + 1; j < d; ++j) s.S2_closed(i, j) = s.S1(i) + s.S1(j) + s.S2(i, j);
  return s;
}

PceSobolIndices pce_sobol_indices(const PolynomialChaosExpansion& e) {
  if (e.constant_output) {
    PceSobolIndices s;
    s.mean = e.coefficients.size() > 0 ? e.coefficients(0) : 0.0;
    s.undefined_reason = "output '" + e.output_name + "' is constant over its runs";
    return s;
  }
  return pce_sobol_indices(e.multi_indices, e.coefficients);
}

bool PceIndicesFixedBySelection::any() const {
  return std::find(S1.begin(), S1.end(), true) != S1.end() || std::find(ST.begin(), ST.end(), true) != ST.end();
}

PceIndicesFixedBySelection pce_indices_fixed_by_selection(const std::vector<MultiIndex>& multi_indices,
                                                          int input_count) {
  const auto d = static_cast<std::size_t>(input_count);
  std::vector<int> alone(d, 0), within(d, 0);  // terms whose support is {i}; terms holding i
  int nonconstant = 0;
  for (const MultiIndex& alpha : multi_indices) {
    const std::vector<int> s = support(alpha);
    if (s.empty()) continue;
    ++nonconstant;
    if (s.size() == 1) ++alone[static_cast<std::size_t>(s[0])];
    for (const int i : s) ++within[static_cast<std::size_t>(i)];
  }
  PceIndicesFixedBySelection fixed{std::vector<bool>(d), std::vector<bool>(d)};
  for (std::size_t i = 0; i < d; ++i) {
    fixed.S1[i] = alone[i] == 0 || alone[i] == nonconstant;
    fixed.ST[i] = within[i] == 0 || within[i] == nonconstant;
  }
  return fixed;
}

PceSobolIntervals bootstrap_pce_sobol(const PolynomialChaosExpansion& e, const DesignMatrix& x,
                                      const Eigen::VectorXd& y, const PceBootstrapSettings& s) {
  check_bootstrap(e, x, y, s);
  const Eigen::Index n = y.size();
  Replicates replicates(static_cast<int>(e.inputs.size()));
  int skipped = 0;
  DesignMatrix xb(n, x.cols());
  Eigen::VectorXd yb(n), coefficients;
  for (int b = 0; b < s.resamples; ++b) {
    stop_if_requested(s.stop, "PCE bootstrap");
    const std::uint64_t key = splitmix64(s.seed ^ splitmix64(kResampleStream + b));
    for (Eigen::Index r = 0; r < n; ++r) {
      const Eigen::Index pick =
          static_cast<Eigen::Index>(splitmix64(key + static_cast<std::uint64_t>(r)) %
                                    static_cast<std::uint64_t>(n));
      xb.row(r) = x.row(pick);
      yb(r) = y(pick);
    }
    const bool ok = refit_pce_coefficients(e, xb, yb, &coefficients);
    const PceSobolIndices si = ok ? pce_sobol_indices(e.multi_indices, coefficients)
                                  : PceSobolIndices{};
    if (!si.defined) {
      ++skipped;
      continue;
    }
    replicates.add(si);
  }
  if (skipped == s.resamples)
    throw std::runtime_error("PCE bootstrap: none of the " + std::to_string(s.resamples) +
                             " resamples of '" + e.output_name + "' could be refitted");
  PceSobolIntervals out = intervals_from(replicates, s.confidence);
  out.resamples_used = s.resamples - skipped;
  out.resamples_skipped = skipped;
  out.fixed_by_selection = pce_indices_fixed_by_selection(e.multi_indices, static_cast<int>(e.inputs.size()));
  return out;
}

}  // namespace rover::study
