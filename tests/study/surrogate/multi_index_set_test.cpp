// Hyperbolic truncation: the total-degree count, a small q-norm set written
// out, fixed inputs, ordering, and the size limit.
#include "study/surrogate/multi_index_set.hpp"

#include <algorithm>
#include <vector>

#include <gtest/gtest.h>

namespace rover::study {
namespace {

TEST(MultiIndexSet, TotalDegreeSetHasBinomialSize) {
  // |{alpha in N^d : |alpha| <= p}| = C(d + p, p).
  EXPECT_EQ(hyperbolic_multi_indices(4, 5, 1.0, std::vector<bool>(4, true)).size(), 126u);
  EXPECT_EQ(hyperbolic_multi_indices(3, 12, 1.0, std::vector<bool>(3, true)).size(), 455u);
}

TEST(MultiIndexSet, HalfNormSetWrittenOut) {
  // sqrt(a1) + sqrt(a2) <= 2.
  const std::vector<MultiIndex> set = hyperbolic_multi_indices(2, 4, 0.5, {true, true});
  const std::vector<MultiIndex> expected{{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2},
                                         {3, 0}, {0, 3}, {4, 0}, {0, 4}};
  EXPECT_EQ(set, expected);
}

TEST(MultiIndexSet, FixedInputsStayAtDegreeZeroAndConstantComesFirst) {
  const std::vector<MultiIndex> set = hyperbolic_multi_indices(3, 3, 0.75, {true, false, true});
  EXPECT_EQ(set.front(), MultiIndex(3, 0));
  for (const MultiIndex& alpha : set) EXPECT_EQ(alpha[1], 0);
  EXPECT_TRUE(std::is_sorted(set.begin(), set.end(), [](const MultiIndex& a, const MultiIndex& b) {
    return total_degree(a) < total_degree(b);
  }));
}

TEST(MultiIndexSet, StopsPastTheSizeLimit) {
  EXPECT_EQ(hyperbolic_multi_indices(10, 6, 1.0, std::vector<bool>(10, true), 100).size(), 101u);
}

}  // namespace
}  // namespace rover::study
