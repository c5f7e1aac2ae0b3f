#pragma once
// A dense cloud written while it is made, for clouds that may not fit in memory: the points'
// records and their visibility go to scratch files (util/scratch_file.h) as they come, and are
// copied into OUT/dense.ply and OUT/dense.ply.vis behind the headers once the count is known.
// The files are byte for byte those of WritePly (float x y z nx ny nz, red green blue; io/ply.h)
// and WritePointVisibility (io/point_visibility.h) for the same points.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "varsfm/util/scratch_file.h"
#include "varsfm/util/types.h"

namespace varsfm {

class PointCloudStream {
 public:
  // Scratch files in `folder` (best on the disk the outputs go to). Throws varsfm::Error when
  // they cannot be made.
  explicit PointCloudStream(const std::filesystem::path& folder);

  // `seen_by`: the ids of the images that see the point (ascending). Throws varsfm::Error when
  // the disk refuses the bytes.
  void Add(const Eigen::Vector3d& position, const Eigen::Vector3d& normal,
           const Eigen::Matrix<uint8_t, 3, 1>& color, const std::vector<image_t>& seen_by);
  size_t size() const { return count_; }

  // Writes the points to `ply` and their visibility to `vis`, each atomically (a temporary beside
  // it, then a rename), and ends the stream: each scratch file is let go once copied, so the disk
  // holds a file's bytes twice at most, not the whole cloud's. Throws varsfm::Error.
  void Write(const std::filesystem::path& ply, const std::filesystem::path& vis) &&;

 private:
  std::optional<ScratchFile> records_;
  std::optional<ScratchFile> visibility_;
  size_t count_ = 0;
  std::vector<char> record_;  // one point's bytes, reused
};

}  // namespace varsfm
