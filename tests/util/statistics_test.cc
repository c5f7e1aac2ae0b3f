#include "varsfm/util/statistics.h"

#include <vector>

#include <gtest/gtest.h>

namespace varsfm {
namespace {

TEST(Median, IsTheElementOfRankHalfTheCount) {
  EXPECT_EQ(Median({}), 0.0);
  EXPECT_EQ(Median({7.5}), 7.5);
  EXPECT_EQ(Median({3, -1, 2}), 2.0);
  // An even count: the upper of the two middle values (a sample, not their mean).
  EXPECT_EQ(Median({4, 1, 3, 2}), 3.0);
  EXPECT_EQ(Median({5, 5, 1, 9, 5, 0}), 5.0);
}

TEST(Quantile, IsTheElementOfRankFractionTimesTheCount) {
  EXPECT_EQ(Quantile({}, 0.9), 0.0);
  const std::vector<double> values = {10, 0, 40, 20, 30};
  EXPECT_EQ(Quantile(values, 0), 0.0);
  EXPECT_EQ(Quantile(values, 0.5), 20.0);
  EXPECT_EQ(Quantile(values, 0.79), 30.0);  // rank floor(3.95) = 3
  EXPECT_EQ(Quantile(values, 0.8), 40.0);   // rank 4
  EXPECT_EQ(Quantile(values, 1), 40.0);     // the largest, not one past it
}

}  // namespace
}  // namespace varsfm
