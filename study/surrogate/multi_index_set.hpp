// Hyperbolic (q-norm) truncation of the polynomial chaos basis (Blatman &
// Sudret 2011, sec. 3.2): the multi-indices alpha in N^d with
//   ||alpha||_q = (sum_i alpha_i^q)^(1/q) <= p,   0 < q <= 1,
// q = 1 being the total-degree set. Smaller q drops high-order interactions
// first while keeping the main effects up to degree p.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

namespace rover::study {

using MultiIndex = std::vector<int>;  // one degree per input

// The set for `dimensions` inputs, degree p and q-norm q; inputs with
// active[i] false get degree 0 only (fixed inputs). Ordered by total degree,
// then lexicographically (largest degree on the first input first); the
// first index is always the zero (constant) index. Assumes p >= 0,
// 0 < q <= 1 and active.size() == dimensions (checked by the callers).
// Enumeration stops once more than max_terms indices are found (then
// max_terms + 1 of them, not a complete set, are returned): the caller can
// refuse an oversized basis without building it.
std::vector<MultiIndex> hyperbolic_multi_indices(
    int dimensions, int degree, double q_norm, const std::vector<bool>& active,
    std::size_t max_terms = std::numeric_limits<std::size_t>::max() - 1);

int total_degree(const MultiIndex& alpha);

}  // namespace rover::study
