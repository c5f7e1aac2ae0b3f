#include "varsfm/matching/image_retrieval.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

// The k best of `scores` (ties by the lower index), those within `radius` of `centre` left out.
std::vector<uint32_t> TopK(const std::vector<float>& scores, size_t centre, size_t radius, int k) {
  std::vector<uint32_t> order;
  order.reserve(scores.size());
  for (uint32_t j = 0; j < scores.size(); ++j)
    if ((j < centre ? centre - j : j - centre) > radius) order.push_back(j);
  const size_t count = std::min(order.size(), static_cast<size_t>(k));
  const auto better = [&](uint32_t a, uint32_t b) {
    return scores[a] != scores[b] ? scores[a] > scores[b] : a < b;
  };
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(count), order.end(),
                    better);
  order.resize(count);
  return order;
}

}  // namespace

void RetrievalOptions::Check() const {
  CheckAtLeast("--retrieval-neighbors", num_neighbors, 1);
  CheckNonNegative("--query-expansion", query_expansion);
}

RetrievalIndex::RetrievalIndex(const std::vector<std::vector<int>>& words, int num_words,
                               RetrievalScoring scoring)
    : scoring_(scoring), inverted_(static_cast<size_t>(std::max(num_words, 0))) {
  // Term counts per image, and in how many images each word occurs.
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> counts(words.size());
  std::vector<uint32_t> images_with_word(inverted_.size(), 0);
  for (size_t k = 0; k < words.size(); ++k) {
    std::vector<int> sorted = words[k];
    std::sort(sorted.begin(), sorted.end());
    for (size_t i = 0; i < sorted.size();) {
      const int word = sorted[i];
      if (word < 0 || word >= num_words)
        Fail("retrieval: word {} outside the vocabulary of {}", word, num_words);
      size_t j = i;
      while (j < sorted.size() && sorted[j] == word) ++j;
      counts[k].emplace_back(static_cast<uint32_t>(word), static_cast<uint32_t>(j - i));
      ++images_with_word[static_cast<size_t>(word)];
      i = j;
    }
  }
  const double n = static_cast<double>(words.size());
  vectors_.resize(words.size());
  for (size_t k = 0; k < words.size(); ++k) {
    BagOfWords vector;
    for (const auto& [word, count] : counts[k]) {
      // Words in every image say nothing (weight 0) and are left out.
      const double idf = std::log(n / images_with_word[word]);
      if (idf > 0) vector.emplace_back(word, static_cast<float>(count * idf));
    }
    vectors_[k] = Normalised(std::move(vector));
    for (const auto& [word, weight] : vectors_[k])
      inverted_[word].emplace_back(static_cast<uint32_t>(k), weight);
  }
}

BagOfWords RetrievalIndex::Normalised(BagOfWords vector) const {
  double norm = 0;
  for (const auto& entry : vector)
    norm += scoring_ == RetrievalScoring::kL1 ? std::abs(entry.second)
                                              : double{entry.second} * entry.second;
  if (scoring_ == RetrievalScoring::kL2) norm = std::sqrt(norm);
  if (norm > 0)
    for (auto& entry : vector) entry.second = static_cast<float>(entry.second / norm);
  return vector;
}

std::vector<float> RetrievalIndex::Scores(const BagOfWords& query) const {
  std::vector<float> scores(vectors_.size(), 0.0f);
  for (const auto& [word, q] : query) {
    if (word >= inverted_.size()) continue;
    for (const auto& [image, d] : inverted_[word])
      scores[image] += scoring_ == RetrievalScoring::kL1 ? 2 * std::min(q, d) : q * d;
  }
  return scores;
}

std::vector<uint32_t> RetrievalIndex::Neighbors(size_t image, const RetrievalOptions& options,
                                                size_t exclude_radius) const {
  std::vector<uint32_t> best =
      TopK(Scores(vectors_[image]), image, exclude_radius, options.num_neighbors);
  if (options.query_expansion == 0 || best.empty()) return best;
  std::map<uint32_t, double> sum;
  for (const auto& [word, weight] : vectors_[image]) sum[word] += weight;
  const size_t m = std::min(best.size(), static_cast<size_t>(options.query_expansion));
  for (size_t r = 0; r < m; ++r)
    for (const auto& [word, weight] : vectors_[best[r]]) sum[word] += weight;
  BagOfWords expanded;
  for (const auto& [word, weight] : sum) expanded.emplace_back(word, static_cast<float>(weight));
  return TopK(Scores(Normalised(std::move(expanded))), image, exclude_radius,
              options.num_neighbors);
}

}  // namespace varsfm
