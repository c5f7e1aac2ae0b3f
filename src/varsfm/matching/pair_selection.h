#pragma once
// Which image pairs to match. Images are given in the order that defines "sequential" (the
// caller sorts them by name, i.e. capture order for photo sets and video frames).
#include <cstdint>
#include <utility>
#include <vector>

#include "varsfm/util/types.h"

namespace varsfm {

using ImagePairs = std::vector<std::pair<image_t, image_t>>;

// Every unordered pair (images[i], images[j]) with i < j, in that order.
ImagePairs ExhaustivePairs(const std::vector<image_t>& images);

// Each image with its next `overlap` images (i < j <= i + overlap), for ordered captures.
ImagePairs SequentialPairs(const std::vector<image_t>& images, int overlap);

// Each image images[i] with its retrieved neighbours images[j], j in neighbors[i] (indices into
// images; see RetrievalIndex::Neighbors), each unordered pair once as (images[min], images[max]),
// in the order of (min, max): the order ExhaustivePairs would give them.
ImagePairs RetrievedPairs(const std::vector<image_t>& images,
                          const std::vector<std::vector<uint32_t>>& neighbors);

// Sequential pairs plus loop closure: every `loop_interval`-th image (0, M, 2M, ...) also with
// its retrieved neighbours (neighbors[i], read only for those images; retrieved beyond the
// sequential overlap, as RetrieveNeighbors' exclude_radius does), so that a walk returning to
// where it started is matched with its start. Ordered as RetrievedPairs.
ImagePairs SequentialLoopPairs(const std::vector<image_t>& images, int overlap, int loop_interval,
                               const std::vector<std::vector<uint32_t>>& neighbors);

}  // namespace varsfm
