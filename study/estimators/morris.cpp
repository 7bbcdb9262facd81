#include "study/estimators/morris.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_int_distribution.hpp>

#include "study/estimators/band_statistics.hpp"

namespace rover::study {

namespace {

// The grid points a trajectory visits from `start`, moving the inputs in
// `order`, as one sequence, or the reversed visit if that sorts first: a
// trajectory and its reverse (which starts where it ends and moves the
// inputs back in the opposite order) give the same elementary effects.
std::vector<int> path_key(std::vector<int> grid, const std::vector<int>& order, int half) {
  const std::size_t d = grid.size();
  std::vector<int> forward(grid);
  for (const int i : order) {
    grid[static_cast<std::size_t>(i)] += grid[static_cast<std::size_t>(i)] < half ? half : -half;
    forward.insert(forward.end(), grid.begin(), grid.end());
  }
  std::vector<int> backward;
  for (std::size_t k = forward.size(); k > 0; k -= d) backward.insert(backward.end(), forward.begin() + (k - d), forward.begin() + k);
  return std::min(forward, backward);
}

}  // namespace

double distinct_morris_trajectories(int dimensions, int levels) {
  // levels^d starts times d! orders (the start sets every jump's direction),
  // each path counted once for its two directions.
  double count = 0.5;
  for (int i = 1; i <= dimensions && count < kManyTrajectories; ++i) count *= static_cast<double>(levels) * i;
  return std::min(count, kManyTrajectories);
}

MorrisDesign morris_design(int dimensions, int trajectories, int levels, std::uint64_t seed) {
  if (dimensions < 1 || trajectories < 1)
    throw std::invalid_argument("morris_design: dimensions and trajectories must be >= 1 (got " +
                                std::to_string(dimensions) + " and " +
                                std::to_string(trajectories) + ")");
  if (levels < 2 || levels % 2 != 0)
    throw std::invalid_argument("morris_design: levels must be even and >= 2 (got " +
                                std::to_string(levels) + ")");
  MorrisDesign design;
  design.trajectories = trajectories;
  design.dimensions = dimensions;
  design.levels = levels;
  const int d = dimensions, half = levels / 2;
  design.points.resize(static_cast<Eigen::Index>(trajectories) * (d + 1), d);
  design.changed_input.reserve(static_cast<std::size_t>(trajectories) * d);
  design.step.reserve(static_cast<std::size_t>(trajectories) * d);
  if (const double distinct = distinct_morris_trajectories(dimensions, levels); trajectories > distinct)
    throw std::invalid_argument("morris_design: " + std::to_string(trajectories) + " trajectories, but " +
                                std::to_string(dimensions) + " input(s) on " + std::to_string(levels) +
                                " levels have only " + std::to_string(static_cast<long long>(distinct)) +
                                " distinct ones; ask for fewer, or for more levels");
  boost::random::mt19937_64 engine(seed);
  boost::random::uniform_int_distribution<int> level(0, levels - 1);
  std::vector<int> grid(static_cast<std::size_t>(d)), order(static_cast<std::size_t>(d));
  std::set<std::vector<int>> drawn;  // each trajectory's path: none repeats
  const auto unit = [levels](int k) { return (k + 0.5) / levels; };
  for (int t = 0; t < trajectories; ++t) {
    const Eigen::Index first = static_cast<Eigen::Index>(t) * (d + 1);
    std::vector<int> key;
    do {
      for (int i = 0; i < d; ++i) grid[i] = level(engine);
      // Random order of the inputs (Fisher-Yates).
      std::iota(order.begin(), order.end(), 0);
      for (int i = d - 1; i > 0; --i)
        std::swap(order[i], order[boost::random::uniform_int_distribution<int>(0, i)(engine)]);
      key = path_key(grid, order, half);
    } while (!drawn.insert(key).second);
    for (int i = 0; i < d; ++i) design.points(first, i) = unit(grid[i]);
    for (int k = 0; k < d; ++k) {
      const int i = order[k];
      const int jump = grid[i] < half ? half : -half;
      design.points.row(first + k + 1) = design.points.row(first + k);
      grid[i] += jump;
      design.points(first + k + 1, i) = unit(grid[i]);
      design.changed_input.push_back(i);
      design.step.push_back(static_cast<double>(jump) / levels);
    }
  }
  return design;
}

MorrisResult morris_effects(const MorrisDesign& design, const Eigen::VectorXd& y,
                            const MorrisOptions& options) {
  const int d = design.dimensions, r = design.trajectories;
  const auto moves = static_cast<std::size_t>(r) * static_cast<std::size_t>(d);
  if (design.points.rows() != static_cast<Eigen::Index>(r) * (d + 1) ||
      design.points.cols() != d || design.changed_input.size() != moves ||
      design.step.size() != moves)
    throw std::invalid_argument("morris_effects: the design's points, changed_input and step do "
                                "not match its " + std::to_string(r) + " trajectories in " +
                                std::to_string(d) + " dimensions");
  if (y.size() != design.points.rows())
    throw std::invalid_argument("morris_effects: " + std::to_string(y.size()) +
                                " outputs for a design of " + std::to_string(r) +
                                " trajectories of " + std::to_string(d + 1) + " runs");
  if (options.bootstrap_resamples < 0 || !(options.confidence > 0.0 && options.confidence < 1.0))
    throw std::invalid_argument(
        "morris_effects: bootstrap_resamples must be >= 0 and confidence in (0, 1)");
  MorrisResult result;
  // effects(t, i): elementary effect of input i on the t-th complete trajectory.
  std::vector<int> used;
  for (int t = 0; t < r; ++t) {
    if (y.segment(static_cast<Eigen::Index>(t) * (d + 1), d + 1).allFinite())
      used.push_back(t);
    else
      result.dropped_trajectories.push_back(t);
  }
  result.trajectories_used = static_cast<int>(used.size());
  if (used.empty())
    throw std::invalid_argument("morris_effects: every one of the " + std::to_string(r) +
                                " trajectories has a failed (non-finite) run");
  const auto n = static_cast<Eigen::Index>(used.size());
  Eigen::MatrixXd effects(n, d);
  for (Eigen::Index u = 0; u < n; ++u) {
    const Eigen::Index first = static_cast<Eigen::Index>(used[u]) * (d + 1);
    for (int k = 0; k < d; ++k) {
      const std::size_t move = static_cast<std::size_t>(used[u]) * d + k;
      effects(u, design.changed_input[move]) = (y[first + k + 1] - y[first + k]) / design.step[move];
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  result.mu = effects.colwise().mean().transpose();
  result.mu_star = effects.cwiseAbs().colwise().mean().transpose();
  result.sigma = Eigen::VectorXd::Constant(d, nan);
  if (n > 1)
    result.sigma = ((effects.rowwise() - result.mu.transpose()).colwise().squaredNorm() /
                    static_cast<double>(n - 1))
                       .cwiseSqrt()
                       .transpose();

  // Bootstrap over trajectories: mu* of each resample from how often each trajectory is drawn.
  result.mu_star_lower = result.mu_star_upper = Eigen::VectorXd::Constant(d, nan);
  const int R = options.bootstrap_resamples;
  if (R > 0) {
    const Eigen::MatrixXd absolute = effects.cwiseAbs();
    Eigen::MatrixXd replicates(d, R);
    Eigen::VectorXd counts(n);
    boost::random::mt19937_64 engine(options.seed);
    boost::random::uniform_int_distribution<Eigen::Index> draw(0, n - 1);
    for (int b = 0; b < R; ++b) {
      counts.setZero();
      for (Eigen::Index k = 0; k < n; ++k) counts[draw(engine)] += 1.0;
      replicates.col(b).noalias() = absolute.transpose() * counts;
    }
    replicates /= static_cast<double>(n);
    const double tail = 0.5 * (1.0 - options.confidence);
    std::vector<double> sorted(static_cast<std::size_t>(R));
    for (int i = 0; i < d; ++i) {
      for (int b = 0; b < R; ++b) sorted[b] = replicates(i, b);
      std::sort(sorted.begin(), sorted.end());
      result.mu_star_lower[i] = quantile(sorted, tail);
      result.mu_star_upper[i] = quantile(sorted, 1.0 - tail);
    }
  }
  result.ranking.resize(static_cast<std::size_t>(d));
  std::iota(result.ranking.begin(), result.ranking.end(), 0);
  std::stable_sort(result.ranking.begin(), result.ranking.end(),
                   [&](int i, int j) { return result.mu_star[i] > result.mu_star[j]; });
  return result;
}

}  // namespace rover::study
