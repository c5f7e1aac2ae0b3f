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

}  // namespace
}  // namespace varsfm
