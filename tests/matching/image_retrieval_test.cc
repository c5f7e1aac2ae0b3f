// TF-IDF retrieval on visual words with exact truth: images along a sequence share words with
// their neighbours in proportion to their overlap, so the best retrieved images are the nearest.
#include "varsfm/matching/image_retrieval.h"

#include <gtest/gtest.h>

#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// Images on a loop: image i holds words 10 i .. 10 i + 49 (modulo 10 n), each twice, plus its
// own 20 words, so images i and j share 50 - 10 d words, d their distance along the loop (none
// beyond 4 apart), and every shared word is in 5 images (the same IDF weight).
std::vector<std::vector<int>> SlidingWords(int num_images, int* num_words) {
  std::vector<std::vector<int>> words(num_images);
  *num_words = 10 * num_images + 20 * num_images;
  for (int i = 0; i < num_images; ++i) {
    for (int w = 10 * i; w < 10 * i + 50; ++w)
      words[i].insert(words[i].end(), {w % (10 * num_images), w % (10 * num_images)});
    for (int u = 0; u < 20; ++u) words[i].push_back(10 * num_images + 20 * i + u);
  }
  return words;
}

class ImageRetrieval : public ::testing::TestWithParam<RetrievalScoring> {};

TEST_P(ImageRetrieval, NearestImagesAreRetrievedFirst) {
  int num_words = 0;
  const auto words = SlidingWords(12, &num_words);
  const RetrievalIndex index(words, num_words, GetParam());
  RetrievalOptions options;
  options.num_neighbors = 2;
  for (uint32_t i = 1; i + 1 < 12; ++i) {
    const std::vector<uint32_t> best = index.Neighbors(i, options);
    ASSERT_EQ(best.size(), 2u);
    // i - 1 and i + 1 share as much with i; ties go to the lower index.
    EXPECT_EQ(best[0], i - 1) << i;
    EXPECT_EQ(best[1], i + 1) << i;
  }
  options.num_neighbors = 4;
  EXPECT_EQ(index.Neighbors(0, options), (std::vector<uint32_t>{1, 11, 2, 10}));
  // Sequential neighbours left out (loop closure): the next best beyond them.
  options.num_neighbors = 2;
  EXPECT_EQ(index.Neighbors(5, options, 1), (std::vector<uint32_t>{3, 7}));
  // More neighbours asked than there are images: all the others.
  options.num_neighbors = 50;
  EXPECT_EQ(index.Neighbors(5, options).size(), 11u);
  // Images with nothing in common score zero.
  const std::vector<float> scores = index.Scores(index.vector(0));
  EXPECT_EQ(scores[6], 0.0f);
  EXPECT_GT(scores[1], scores[2]);
  EXPECT_NEAR(scores[0], GetParam() == RetrievalScoring::kL1 ? 2.0f : 1.0f, 1e-5);
}

TEST_P(ImageRetrieval, QueryExpansionReachesNeighboursOfNeighbours) {
  // Image 0 shares words with 1 only, 1 with 0 and 2; image 2 (nothing in common with 0) is
  // found through 1 when 1 is averaged into 0's query.
  const std::vector<std::vector<int>> words = {
      {0, 1, 2, 3, 10}, {2, 3, 4, 5, 11}, {4, 5, 6, 7, 12}, {20, 21, 22, 23, 13}, {30, 31, 14}};
  const RetrievalIndex index(words, 40, GetParam());
  RetrievalOptions options;
  options.num_neighbors = 2;
  const std::vector<uint32_t> plain = index.Neighbors(0, options);
  EXPECT_EQ(plain[0], 1u);
  EXPECT_EQ(index.Scores(index.vector(0))[2], 0.0f);
  options.query_expansion = 1;
  EXPECT_EQ(index.Neighbors(0, options), (std::vector<uint32_t>{1, 2}));
}

INSTANTIATE_TEST_SUITE_P(Scorings, ImageRetrieval,
                         ::testing::Values(RetrievalScoring::kL1, RetrievalScoring::kL2));

TEST(ImageRetrievalOptions, AreChecked) {
  RetrievalOptions options;
  EXPECT_NO_THROW(options.Check());
  options.num_neighbors = 0;
  EXPECT_THROW(options.Check(), OptionError);
  options = {};
  options.query_expansion = -1;
  EXPECT_THROW(options.Check(), OptionError);
}

}  // namespace
}  // namespace varsfm
