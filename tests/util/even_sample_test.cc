#include "varsfm/util/even_sample.h"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace varsfm {
namespace {

TEST(EvenSample, KeepsAllUpToTwiceTheCap) {
  EvenSample<int> sample(5);
  for (int i = 0; i < 9; ++i) sample.Add(i);
  EXPECT_EQ(sample.items(), (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST(EvenSample, EveryPowerOfTwoStrideFromTheFirst) {
  for (int n : {10, 11, 100, 1000, 12345}) {
    EvenSample<int> sample(10);
    for (int i = 0; i < n; ++i) sample.Add(i);
    const std::vector<int>& items = sample.items();
    ASSERT_GE(items.size(), 2u) << n;
    EXPECT_LT(items.size(), 20u) << n;
    const int stride = items[1] - items[0];
    EXPECT_EQ(stride & (stride - 1), 0) << n;  // a power of two
    for (size_t i = 0; i < items.size(); ++i) EXPECT_EQ(items[i], static_cast<int>(i) * stride);
    // The last item kept is within one stride of the end: the sample spans the whole stream.
    EXPECT_GT(items.back() + stride, n - 1) << n;
  }
}

TEST(EvenSample, KeepsItsFirstItemWhenTheStrideDoubles) {
  // Items that a move empties: the first one stays in place, not moved onto itself.
  EvenSample<std::string> sample(2);
  for (int i = 0; i < 9; ++i) sample.Add("item" + std::to_string(i));
  EXPECT_EQ(sample.items(), (std::vector<std::string>{"item0", "item4", "item8"}));
}

}  // namespace
}  // namespace varsfm
