// See multi_index_set.hpp.
#include "study/surrogate/multi_index_set.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace rover::study {
namespace {

// ||alpha||_q^q <= p^q is compared with this relative slack, so that indices
// exactly on the boundary (e.g. (p, 0, ...)) are not lost to rounding.
constexpr double kBoundaryTolerance = 1e-9;

struct Enumeration {
  int dimensions;
  int degree;
  double q_norm;
  double budget;  // p^q
  const std::vector<bool>* active;
  std::size_t max_terms;
  std::vector<MultiIndex>* out;
};

// Fills alpha[dim ..] in every admissible way, given the q-th power sum so far.
void enumerate(const Enumeration& e, int dim, double used, MultiIndex* alpha) {
  if (e.out->size() > e.max_terms) return;
  if (dim == e.dimensions) {
    e.out->push_back(*alpha);
    return;
  }
  const int top = (*e.active)[dim] ? e.degree : 0;
  for (int k = 0; k <= top; ++k) {
    const double cost = k == 0 ? 0.0 : std::pow(static_cast<double>(k), e.q_norm);
    if (used + cost > e.budget * (1.0 + kBoundaryTolerance)) break;
    (*alpha)[dim] = k;
    enumerate(e, dim + 1, used + cost, alpha);
  }
  (*alpha)[dim] = 0;
}

}  // namespace

int total_degree(const MultiIndex& alpha) { return std::accumulate(alpha.begin(), alpha.end(), 0); }

std::vector<MultiIndex> hyperbolic_multi_indices(int dimensions, int degree, double q_norm,
                                                 const std::vector<bool>& active,
                                                 std::size_t max_terms) {
  std::vector<MultiIndex> out;
  const Enumeration e{dimensions, degree, q_norm, std::pow(static_cast<double>(degree), q_norm),
                      &active, max_terms, &out};
  MultiIndex alpha(dimensions, 0);
  enumerate(e, 0, 0.0, &alpha);
  std::stable_sort(out.begin(), out.end(), [](const MultiIndex& x, const MultiIndex& y) {
    const int dx = total_degree(x), dy = total_degree(y);
    if (dx != dy) return dx < dy;
    return std::lexicographical_compare(y.begin(), y.end(), x.begin(), x.end());
  });
  return out;
}

}  // namespace rover::study
