#pragma once
// Which images see each point of a dense cloud, beside the cloud: OUT/dense.ply.vis in the
// layout of COLMAP's fused.ply.vis (little-endian: uint64 point count, then per point a uint32
// count and that many uint32 image ids), in the cloud's point order. A visibility-based surface
// (rays from each camera to the points it sees) reads it.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include "varsfm/util/types.h"

namespace varsfm {

// Per point, the ids of the images that see it (ascending).
using PointVisibility = std::vector<std::vector<image_t>>;

// Writes atomically (a temporary beside `file`, then a rename). Throws varsfm::Error.
void WritePointVisibility(const std::filesystem::path& file, const PointVisibility& visibility);

// Throws varsfm::Error for a missing, truncated or inconsistent file.
PointVisibility ReadPointVisibility(const std::filesystem::path& file);

// ReadPointVisibility one point at a time, for a cloud read as it is merged (surface_input.h).
// Throws varsfm::Error as ReadPointVisibility.
class PointVisibilityReader {
 public:
  explicit PointVisibilityReader(const std::filesystem::path& file);  // reads the count
  size_t size() const { return count_; }
  // The next point's image ids (at most size() points).
  void Next(std::vector<image_t>* ids);
  // Throws varsfm::Error unless every point was read and the file ends there.
  void ExpectEnd();

 private:
  std::filesystem::path file_;
  std::ifstream in_;
  uintmax_t bytes_ = 0;
  size_t count_ = 0;
  size_t next_ = 0;
  std::vector<char> bytes_read_;  // one point's ids as stored
};

}  // namespace varsfm
