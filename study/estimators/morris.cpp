#include "study/estimators/morris.hpp"
#include "study/estimators/work_stopped.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>

#include <boost/random/mersenne_twister.hpp>
#include <boost/random/uniform_int_distribution.hpp>

#include "study/estimators/band_statistics.hpp"

namespace rover::study {

namespace {

using Engine = boost::random::mt19937_64;

// Random draws that keep colliding with earlier trajectories' steps this many
// times in a row mean the design is near its bound: it is packed instead.
constexpr int kDrawsPerTrajectory = 200;

// A trajectory on the grid: the levels of its start and the order in which
// the inputs move (each by half the levels, up from the lower half, down from
// the upper).
struct GridTrajectory {
  std::vector<int> start, order;
};

// The step of each input a trajectory takes: the levels before the move with
// the moving input's level replaced by the lower of its pair {k, k + half},
// then the input.
std::vector<std::vector<int>> steps_of(const GridTrajectory& t, int half) {
  std::vector<int> grid = t.start;
  std::vector<std::vector<int>> steps;
  for (const int i : t.order) {
    std::vector<int> step = grid;
    step[static_cast<std::size_t>(i)] %= half;
    step.push_back(i);
    steps.push_back(std::move(step));
    grid[static_cast<std::size_t>(i)] += grid[static_cast<std::size_t>(i)] < half ? half : -half;
  }
  return steps;
}

std::vector<int> random_order(int d, Engine& engine) {
  std::vector<int> order(static_cast<std::size_t>(d));
  std::iota(order.begin(), order.end(), 0);  // then Fisher-Yates
  for (int i = d - 1; i > 0; --i)
    std::swap(order[i], order[boost::random::uniform_int_distribution<int>(0, i)(engine)]);
  return order;
}

// Morris's random trajectories, each redrawn while one of its steps repeats
// an earlier trajectory's; empty if one found no free steps in
// kDrawsPerTrajectory draws.
std::vector<GridTrajectory> drawn_trajectories(int d, int trajectories, int levels, Engine& engine) {
  boost::random::uniform_int_distribution<int> level(0, levels - 1);
  std::set<std::vector<int>> taken;
  std::vector<GridTrajectory> drawn;
  for (int t = 0; t < trajectories; ++t) {
    for (int draw = 0;; ++draw) {
      if (draw == kDrawsPerTrajectory) return {};
      GridTrajectory candidate{std::vector<int>(static_cast<std::size_t>(d)), {}};
      for (int& k : candidate.start) k = level(engine);
      candidate.order = random_order(d, engine);
      const std::vector<std::vector<int>> steps = steps_of(candidate, levels / 2);
      if (std::any_of(steps.begin(), steps.end(), [&](const auto& s) { return taken.contains(s); })) continue;
      taken.insert(steps.begin(), steps.end());
      drawn.push_back(std::move(candidate));
      break;
    }
  }
  return drawn;
}

// A packing of distinct_morris_steps trajectories that share no step. The
// grid splits into classes by each input's pair (its level mod half); a step
// never leaves its class. Within a class, the 2^d points are the corners of a
// cube (which half of its pair each input is in); every trajectory of the
// class moves the inputs in one order and starts at a corner of one parity
// (both random per class). Two such starts differ in at least two inputs'
// halves, so the points before input i moves differ in some other input:
// no step repeats. The design draws `trajectories` of the packing at random.
std::vector<GridTrajectory> packed_trajectories(int d, int trajectories, int levels, Engine& engine) {
  const int half = levels / 2;
  struct ClassLayout {
    std::vector<int> order;
    int parity = 0;
  };
  std::map<std::vector<int>, ClassLayout> classes;
  std::set<std::vector<int>> starts;
  std::vector<GridTrajectory> packed;
  boost::random::uniform_int_distribution<int> pair(0, half - 1), bit(0, 1);
  while (static_cast<int>(packed.size()) < trajectories) {
    std::vector<int> pairs(static_cast<std::size_t>(d)), halves(static_cast<std::size_t>(d));
    for (int& p : pairs) p = pair(engine);
    auto layout = classes.find(pairs);
    if (layout == classes.end()) layout = classes.emplace(pairs, ClassLayout{random_order(d, engine), bit(engine)}).first;
    int parity = layout->second.parity;
    for (int i = 0; i + 1 < d; ++i) parity ^= halves[static_cast<std::size_t>(i)] = bit(engine);
    halves.back() = parity;
    std::vector<int> start(static_cast<std::size_t>(d));
    for (int i = 0; i < d; ++i) start[i] = pairs[i] + half * halves[i];
    if (starts.insert(start).second) packed.push_back({std::move(start), layout->second.order});
  }
  return packed;
}

}  // namespace

double distinct_morris_steps(int dimensions, int levels) {
  // levels / 2 pairs of levels of the moving input, times levels^(d-1) of the others.
  double count = 0.5 * levels;
  for (int i = 1; i < dimensions && count < kManySteps; ++i) count *= static_cast<double>(levels);
  return std::min(count, kManySteps);
}

MorrisDesign morris_design(int dimensions, int trajectories, int levels, std::uint64_t seed) {
  if (dimensions < 1 || trajectories < 1)
    throw std::invalid_argument("morris_design: dimensions and trajectories must be >= 1 (got " +
                                std::to_string(dimensions) + " and " +
                                std::to_string(trajectories) + ")");
  if (levels < 2 || levels % 2 != 0)
    throw std::invalid_argument("morris_design: levels must be even and >= 2 (got " +
                                std::to_string(levels) + ")");
  if (const double distinct = distinct_morris_steps(dimensions, levels); trajectories > distinct)
    throw std::invalid_argument("morris_design: " + std::to_string(trajectories) + " trajectories, but " +
                                std::to_string(dimensions) + " input(s) on " + std::to_string(levels) +
                                " levels give each input only " + std::to_string(static_cast<long long>(distinct)) +
                                " distinct steps; ask for at most that many, or for more levels");
  MorrisDesign design;
  design.trajectories = trajectories;
  design.dimensions = dimensions;
  design.levels = levels;
  const int d = dimensions, half = levels / 2;
  design.points.resize(static_cast<Eigen::Index>(trajectories) * (d + 1), d);
  design.changed_input.reserve(static_cast<std::size_t>(trajectories) * d);
  design.step.reserve(static_cast<std::size_t>(trajectories) * d);
  Engine engine(seed);
  std::vector<GridTrajectory> chosen = drawn_trajectories(d, trajectories, levels, engine);
  if (chosen.empty()) chosen = packed_trajectories(d, trajectories, levels, engine);
  const auto unit = [levels](int k) { return static_cast<double>(k) / (levels - 1); };
  for (int t = 0; t < trajectories; ++t) {
    const Eigen::Index first = static_cast<Eigen::Index>(t) * (d + 1);
    std::vector<int> grid = chosen[static_cast<std::size_t>(t)].start;
    for (int i = 0; i < d; ++i) design.points(first, i) = unit(grid[i]);
    for (int k = 0; k < d; ++k) {
      const int i = chosen[static_cast<std::size_t>(t)].order[static_cast<std::size_t>(k)];
      const int jump = grid[i] < half ? half : -half;
      design.points.row(first + k + 1) = design.points.row(first + k);
      grid[i] += jump;
      design.points(first + k + 1, i) = unit(grid[i]);
      design.changed_input.push_back(i);
      design.step.push_back(static_cast<double>(jump) / (levels - 1));
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
  if (static_cast<int>(used.size()) < kMinMorrisTrajectories)
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
  result.has_intervals = R > 0 && n >= kMinBootstrapMorrisTrajectories;
  if (result.has_intervals) {
    const Eigen::MatrixXd absolute = effects.cwiseAbs();
    Eigen::MatrixXd replicates(d, R);
    Eigen::VectorXd counts(n);
    boost::random::mt19937_64 engine(options.seed);
    boost::random::uniform_int_distribution<Eigen::Index> draw(0, n - 1);
    for (int b = 0; b < R; ++b) {
      stop_if_requested(options.stop, "Morris effects: bootstrap");
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
