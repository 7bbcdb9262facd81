// Sampling designs of the studies: points in the unit cube, mapped to the
// inputs' distributions by their quantiles (inverse-transform sampling).
//
//  monte_carlo      independent uniform points; point i has its own
//                   Boost.Random mt19937_64 seeded from a SplitMix64 hash
//                   (Steele, Lea and Flood 2014) of (seed, i).
//  latin_hypercube  McKay, Beckman and Conover (1979): each column a random
//                   permutation of the n strata [k/n, (k+1)/n), a uniform
//                   jitter inside each stratum.
//  sobol            the Sobol' (1967) sequence, Joe and Kuo (2008) direction
//                   numbers (boost::random::sobol), randomised by Owen's
//                   (1995) nested uniform scrambling in base 2: the i-th
//                   binary digit of a coordinate is flipped or not according
//                   to a random bit keyed by (seed, dimension, i, the digits
//                   above it). The random bits come from a keyed SplitMix64
//                   hash, so no permutation tables are stored and point i
//                   depends only on (seed, i). Scrambling keeps the (t, m, s)-net
//                   structure, makes every point uniform on the cube and the
//                   RMS integration error of smooth integrands
//                   O(n^-3/2 (log n)^((d-1)/2)) (Owen 1997). The sequence starts at its point 0 (the
//                   origin before scrambling), so the first 2^m points form a
//                   net.
//  grid             the full factorial of unit_grid (not a unit_design).
//
// All functions are pure; they may run concurrently.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "study/estimators/design_matrix.hpp"
#include "study/estimators/distributions.hpp"

namespace rover::study {

// One row per sample, one column per dimension (input).

enum class DesignType { kMonteCarlo, kLatinHypercube, kSobol, kGrid };

// "monte_carlo", "latin_hypercube", "sobol", "grid".
const char* design_type_name(DesignType type);
// The inverse of design_type_name; throws std::invalid_argument listing the
// valid names.
DesignType design_type_from_name(const std::string& name);

// The most dimensions a Sobol' design can have (Boost's Joe-Kuo table).
int sobol_max_dimensions();

// samples x dimensions points in the OPEN unit cube (0, 1)^d, never 0 or 1:
// monte_carlo and sobol coordinates are odd multiples of 2^-53 (the centre of
// a cell of 2^-52), latin_hypercube ones lie strictly inside their stratum.
//  monte_carlo, sobol: point i depends only on (seed, i), so the first k rows
//               of an n-point design equal the k-point design.
//  latin_hypercube: drawn whole from the seed.
// Throws std::invalid_argument for samples < 1, dimensions < 1, a Sobol'
// design with more than sobol_max_dimensions() dimensions, or kGrid. Once
// `stop` (if given) is set, throws WorkStopped within kRowsBetweenStopChecks
// rows (a design of 10^8 Monte Carlo points takes minutes to draw).
inline constexpr int kRowsBetweenStopChecks = 4096;
DesignMatrix unit_design(DesignType type, int samples, int dimensions, std::uint64_t seed,
                         const std::atomic<bool>* stop = nullptr);

// Full factorial: levels[j] points on axis j at k / (levels[j] - 1), k = 0 ..
// levels[j] - 1 (0 and 1 included; a single level is 0.5); rows ordered with
// the LAST axis varying fastest. Throws std::invalid_argument on no axes, a
// level count < 1, or a total number of points that overflows int.
DesignMatrix unit_grid(const std::vector<int>& levels);

// One axis of a grid in physical units: n values from `min` to `max`
// inclusive, evenly spaced (log_grid: evenly in log10, the end points exact;
// a single value is `min`). Throws std::invalid_argument for n < 1, and
// log_grid for bounds that are not positive.
std::vector<double> linear_grid(double min, double max, int n);
std::vector<double> log_grid(double min, double max, int n);

// x_ij = distributions[j].quantile(u_ij). Throws std::invalid_argument if the
// column count differs from distributions.size() or a distribution is not
// IsValid(); std::domain_error (from quantile) for u = 0 or 1 on an infinite
// end of a support (e.g. a grid's end points mapped to a normal).
DesignMatrix map_to_distributions(const DesignMatrix& unit,
                                  const std::vector<Distribution>& distributions);

// Centred L2 discrepancy of n points in [0, 1]^d (Hickernell 1998), from its
// closed form
//   CD^2 = (13/12)^d - 2/n sum_i prod_k (1 + |x_ik - 1/2| / 2 - |x_ik - 1/2|^2 / 2)
//        + 1/n^2 sum_i sum_j prod_k (1 + |x_ik - 1/2| / 2 + |x_jk - 1/2| / 2
//                                      - |x_ik - x_jk| / 2)),
// returned as CD (not squared). O(n^2 d): for tests and reports.
double centered_l2_discrepancy(const DesignMatrix& unit);

}  // namespace rover::study
