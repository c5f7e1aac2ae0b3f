#include "varsfm/matching/pair_selection.h"

#include <algorithm>

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

}  // namespace varsfm
