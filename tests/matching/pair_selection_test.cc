#include "varsfm/matching/pair_selection.h"

#include <gtest/gtest.h>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

TEST(PairSelection, ExhaustiveListsEveryPairOnce) {
  const ImagePairs pairs = ExhaustivePairs({4, 2, 9, 1});
  const ImagePairs expected = {{4, 2}, {4, 9}, {4, 1}, {2, 9}, {2, 1}, {9, 1}};
  EXPECT_EQ(pairs, expected);
  EXPECT_TRUE(ExhaustivePairs({}).empty());
  EXPECT_TRUE(ExhaustivePairs({3}).empty());
  std::vector<image_t> many(11);
  for (image_t i = 0; i < 11; ++i) many[i] = i + 1;
  EXPECT_EQ(ExhaustivePairs(many).size(), 55u);
}

TEST(PairSelection, SequentialPairsEachImageWithItsNextOverlap) {
  const ImagePairs pairs = SequentialPairs({1, 2, 3, 4, 5}, 2);
  const ImagePairs expected = {{1, 2}, {1, 3}, {2, 3}, {2, 4}, {3, 4}, {3, 5}, {4, 5}};
  EXPECT_EQ(pairs, expected);
  // An overlap beyond the sequence is exhaustive matching.
  EXPECT_EQ(SequentialPairs({1, 2, 3, 4, 5}, 10), ExhaustivePairs({1, 2, 3, 4, 5}));
  EXPECT_THROW(SequentialPairs({1, 2}, 0), Error);
}

TEST(PairSelection, RetrievedPairsOnceInExhaustiveOrder) {
  // Mutual neighbours (0 and 2) give one pair; orientation as ExhaustivePairs.
  const ImagePairs pairs = RetrievedPairs({7, 3, 5, 9}, {{2, 1}, {0}, {0, 3}, {1}});
  const ImagePairs expected = {{7, 3}, {7, 5}, {3, 9}, {5, 9}};
  EXPECT_EQ(pairs, expected);
  EXPECT_THROW(RetrievedPairs({1, 2}, {{1}}), Error);
  EXPECT_THROW(RetrievedPairs({1, 2}, {{5}, {}}), Error);
}

TEST(PairSelection, SequentialLoopPairsCloseTheLoopEveryInterval) {
  const std::vector<image_t> images = {1, 2, 3, 4, 5, 6, 7};
  // Image 6 (index 6) is where the walk returns to image 0; the neighbours of images the
  // interval skips (index 1) are not read.
  const std::vector<std::vector<uint32_t>> neighbors = {{6, 1}, {5}, {}, {}, {}, {}, {0}};
  const ImagePairs pairs = SequentialLoopPairs(images, 1, 3, neighbors);
  const ImagePairs expected = {{1, 2}, {1, 7}, {2, 3}, {3, 4}, {4, 5}, {5, 6}, {6, 7}};
  EXPECT_EQ(pairs, expected);
  EXPECT_THROW(SequentialLoopPairs(images, 1, 0, neighbors), Error);
}

}  // namespace
}  // namespace varsfm
