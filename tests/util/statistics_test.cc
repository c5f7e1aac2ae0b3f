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

}  // namespace
}  // namespace varsfm
