// median(): the statistic every timing in rayscout reports.
#include <gtest/gtest.h>

#include <vector>

#include "rayscout/core/median.h"

namespace rayscout {
namespace {

TEST(Median, MiddleValueOrMeanOfTheTwoMiddleOnes) {
  EXPECT_EQ(median({7.0}), 7.0);
  EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);             // unsorted input
  EXPECT_EQ(median({4.0, 1.0, 10.0, 2.0}), 3.0);       // (2 + 4) / 2, not 4 or 2
  EXPECT_EQ(median({5.0, 5.0, 1.0, 100.0, 2.0}), 5.0);  // an outlier does not move it
}

TEST(Median, MeanOfTwoHugeMiddleValuesIsFinite) {
  EXPECT_EQ(median({1e308, 1.5e308}), 1.25e308);  // 0.5 * (a + b) gave inf
}

}  // namespace
}  // namespace rayscout
