#pragma once
// Image retrieval with a vocabulary tree (Nistér & Stewénius 2006): each image is a bag of
// visual words weighted by TF-IDF, w_i = ln(N / N_i) for word i seen in N_i of the N indexed
// images; images are compared through an inverted file, by the L1 distance of the L1-normalised
// vectors (the paper's choice, its eq. 5: only words both images hold are visited) or the dot
// product of L2-normalised ones. Optional average query expansion (Chum et al., "Total Recall",
// ICCV 2007): a second query with the image's vector plus those of its best matches reaches
// images that share content with its neighbours (neighbours of neighbours).
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "varsfm/util/enum_names.h"

namespace varsfm {

enum class RetrievalScoring {
  kL1,  // 2 - |q - d|_1 of L1-normalised vectors = 2 sum_i min(q_i, d_i)
  kL2,  // q . d of L2-normalised vectors
};

// The names `--retrieval-scoring` takes.
inline constexpr EnumName<RetrievalScoring> kRetrievalScoringNames[] = {
    {RetrievalScoring::kL1, "l1"}, {RetrievalScoring::kL2, "l2"}};

struct RetrievalOptions {
  // Top-k retrieved images each image is matched with: 30 found 88 % of the inliers of
  // exhaustive matching on a rendered 240-image walk, with the same model accuracy
  // (bench/results/2026-12-02-retrieval.md).
  int num_neighbors = 30;
  // Best matches averaged into a second query (0: no query expansion).
  int query_expansion = 0;
  RetrievalScoring scoring = RetrievalScoring::kL1;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

// A TF-IDF vector: (word, weight) sorted by word.
using BagOfWords = std::vector<std::pair<uint32_t, float>>;

class RetrievalIndex {
 public:
  // Images are indexed 0 .. n - 1 in the order given; words[k] holds image k's visual word per
  // descriptor. IDF weights come from these images.
  RetrievalIndex(const std::vector<std::vector<int>>& words, int num_words,
                 RetrievalScoring scoring);

  size_t size() const { return vectors_.size(); }
  const BagOfWords& vector(size_t image) const { return vectors_[image]; }

  // Similarity of `query` to every indexed image.
  std::vector<float> Scores(const BagOfWords& query) const;

  // The `k` images most similar to image `image`, best first, ties by index, leaving out the
  // image and those less than or exactly `exclude_radius` places from it (loop closure: the
  // sequential neighbours, matched anyway); with query_expansion m > 0, those of the second
  // query made of the image and its m best.
  std::vector<uint32_t> Neighbors(size_t image, const RetrievalOptions& options,
                                  size_t exclude_radius = 0) const;

 private:
  BagOfWords Normalised(BagOfWords vector) const;

  RetrievalScoring scoring_;
  std::vector<BagOfWords> vectors_;
  // Per word: (image, weight) in image order.
  std::vector<std::vector<std::pair<uint32_t, float>>> inverted_;
};

}  // namespace varsfm
