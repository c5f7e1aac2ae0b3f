#pragma once
// A uniform hash grid over a point set: voxel-grid downsampling (so that Poisson sees an even
// density and a bounded point count) and nearest-point queries within one cell size (used to
// trim surface parts far from the data and to colour mesh vertices).
#include <optional>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "varsfm/scene/point_cloud.h"

namespace varsfm {

// Replaces the points of each voxel_size cube by their mean (normals: normalised mean, colours:
// mean, visibility: the union). voxel_size <= 0 returns the cloud unchanged.
PointCloud VoxelDownsample(const PointCloud& cloud, double voxel_size);

// VoxelDownsample at voxel_size (> 0), or, where that leaves more than max_points points, at a
// voxel grown until at most max_points remain. Points sample surfaces, so their count falls
// about as the square of the voxel size: each step grows it by that estimate (at least 1.1x)
// rather than by a fixed factor, which took ~6 passes over a million points. The size used is
// written to *used_voxel_size when given.
PointCloud VoxelDownsampleAtMost(const PointCloud& cloud, size_t max_points, double voxel_size,
                                 double* used_voxel_size = nullptr);

class PointGrid {
 public:
  PointGrid(const std::vector<Eigen::Vector3d>& points, double cell_size);
  // Index of the nearest point within cell_size of `query`, if any.
  std::optional<size_t> NearestWithinCell(const Eigen::Vector3d& query) const;

 private:
  const std::vector<Eigen::Vector3d>& points_;
  double cell_size_;
  std::unordered_map<uint64_t, std::vector<size_t>> cells_;
};

}  // namespace varsfm
