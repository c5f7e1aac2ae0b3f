#pragma once
// The retrieval half of `varsfm match --strategy retrieval` and of sequential matching's loop
// closure: a vocabulary tree trained on a sample of the workspace's own descriptors (or read from
// --vocabulary), every image's descriptors quantized into visual words, and each queried image's
// top-k most similar images (matching/image_retrieval.h).
#include <cstdint>
#include <vector>

#include "varsfm/io/database.h"
#include "varsfm/pipeline/match.h"

namespace varsfm {

// Neighbours (indices into `images`) of each image i with is_query[i], leaving out images up
// to exclude_radius places from it (RetrievalIndex::Neighbors); empty lists for the others.
// Descriptors are read from the database one image at a time (twice: once for the training sample,
// once to quantize), so memory holds one image's descriptors and every image's words, not every
// descriptor. The same lists at any thread count.
std::vector<std::vector<uint32_t>> RetrieveNeighbors(const Database& db,
                                                     const std::vector<image_t>& images,
                                                     const std::vector<bool>& is_query,
                                                     const MatchOptions& options,
                                                     size_t exclude_radius = 0);

}  // namespace varsfm
