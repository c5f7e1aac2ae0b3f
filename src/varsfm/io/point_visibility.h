#pragma once
// Which images see each point of a dense cloud, beside the cloud: OUT/dense.ply.vis in the
// layout of COLMAP's fused.ply.vis (little-endian: uint64 point count, then per point a uint32
// count and that many uint32 image ids), in the cloud's point order. A visibility-based surface
// (rays from each camera to the points it sees) reads it.
#include <filesystem>
#include <vector>

#include "varsfm/util/types.h"

namespace varsfm {

// Per point, the ids of the images that see it (ascending).
using PointVisibility = std::vector<std::vector<image_t>>;

// Writes atomically (a temporary beside `file`, then a rename). Throws varsfm::Error.
void WritePointVisibility(const std::filesystem::path& file, const PointVisibility& visibility);

// Throws varsfm::Error for a missing, truncated or inconsistent file.
PointVisibility ReadPointVisibility(const std::filesystem::path& file);

}  // namespace varsfm
