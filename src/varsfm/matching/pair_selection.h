#pragma once
// Which image pairs to match. Images are given in the order that defines "sequential" (the
// caller sorts them by name, i.e. capture order for photo sets and video frames).
#include <utility>
#include <vector>

#include "varsfm/util/types.h"

namespace varsfm {

using ImagePairs = std::vector<std::pair<image_t, image_t>>;

// Every unordered pair (images[i], images[j]) with i < j, in that order.
ImagePairs ExhaustivePairs(const std::vector<image_t>& images);

// Each image with its next `overlap` images (i < j <= i + overlap), for ordered captures.
ImagePairs SequentialPairs(const std::vector<image_t>& images, int overlap);

}  // namespace varsfm
