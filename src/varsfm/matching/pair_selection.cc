#include "varsfm/matching/pair_selection.h"

#include <algorithm>
#include <set>

#include "varsfm/util/error.h"

namespace varsfm {

ImagePairs ExhaustivePairs(const std::vector<image_t>& images) {
  ImagePairs pairs;
  pairs.reserve(images.size() * (images.size() - (images.empty() ? 0 : 1)) / 2);
  for (size_t i = 0; i < images.size(); ++i) {
    for (size_t j = i + 1; j < images.size(); ++j) pairs.emplace_back(images[i], images[j]);
  }
  return pairs;
}

ImagePairs SequentialPairs(const std::vector<image_t>& images, int overlap) {
  if (overlap < 1) Fail("sequential matching needs an overlap of at least 1, got {}", overlap);
  ImagePairs pairs;
  for (size_t i = 0; i < images.size(); ++i) {
    const size_t last = std::min(images.size() - 1, i + static_cast<size_t>(overlap));
    for (size_t j = i + 1; j <= last; ++j) pairs.emplace_back(images[i], images[j]);
  }
  return pairs;
}

namespace {

using IndexPairs = std::set<std::pair<size_t, size_t>>;

void AddNeighbors(size_t i, const std::vector<uint32_t>& neighbors, size_t num_images,
                  IndexPairs& pairs) {
  for (const uint32_t j : neighbors) {
    if (j >= num_images) Fail("retrieved image {} of {} images", j, num_images);
    if (j != i) pairs.emplace(std::min<size_t>(i, j), std::max<size_t>(i, j));
  }
}

ImagePairs ToImagePairs(const std::vector<image_t>& images, const IndexPairs& pairs) {
  ImagePairs result;
  result.reserve(pairs.size());
  for (const auto& [i, j] : pairs) result.emplace_back(images[i], images[j]);
  return result;
}

}  // namespace

ImagePairs RetrievedPairs(const std::vector<image_t>& images,
                          const std::vector<std::vector<uint32_t>>& neighbors) {
  if (neighbors.size() != images.size())
    Fail("{} neighbour lists for {} images", neighbors.size(), images.size());
  IndexPairs pairs;
  for (size_t i = 0; i < images.size(); ++i) AddNeighbors(i, neighbors[i], images.size(), pairs);
  return ToImagePairs(images, pairs);
}

ImagePairs SequentialLoopPairs(const std::vector<image_t>& images, int overlap, int loop_interval,
                               const std::vector<std::vector<uint32_t>>& neighbors) {
  if (overlap < 1) Fail("sequential matching needs an overlap of at least 1, got {}", overlap);
  if (loop_interval < 1)
    Fail("loop closure needs an interval of at least 1, got {}", loop_interval);
  if (neighbors.size() != images.size())
    Fail("{} neighbour lists for {} images", neighbors.size(), images.size());
  IndexPairs pairs;
  for (size_t i = 0; i < images.size(); ++i) {
    const size_t last = std::min(images.size() - 1, i + static_cast<size_t>(overlap));
    for (size_t j = i + 1; j <= last; ++j) pairs.emplace(i, j);
    if (i % static_cast<size_t>(loop_interval) == 0)
      AddNeighbors(i, neighbors[i], images.size(), pairs);
  }
  return ToImagePairs(images, pairs);
}

}  // namespace varsfm
