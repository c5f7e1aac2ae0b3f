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

// Points merged per voxel as they come (VoxelDownsample's merge, for a cloud read point by point:
// surface_input.h): per voxel the mean position, the normalised mean normal, the mean colour and
// the union of the visibility, of the parts the constructor names.
class VoxelMerge {
 public:
  VoxelMerge(double voxel_size, bool normals, bool colors, bool visibility);
  // `normal`, `color` and `visibility` are read where the constructor asked for them.
  void Add(const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
           const Eigen::Matrix<uint8_t, 3, 1>& color, const std::vector<uint32_t>& visibility);
  size_t size() const { return voxels_.size(); }  // voxels so far
  // The merged points, in the order their voxels were first met (viewpoints left empty). A voxel
  // whose normals cancel (the two sides of a thin wall) is dropped rather than given an
  // arbitrary orientation.
  PointCloud Result() &&;

 private:
  struct Voxel {
    Eigen::Vector3d point = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::Zero(),
                    color = Eigen::Vector3d::Zero();
    int count = 0;
    std::vector<uint32_t> views;  // ascending, unique
  };
  double voxel_size_;
  bool normals_, colors_, visibility_;
  std::unordered_map<uint64_t, size_t> slot_;
  std::vector<Voxel> voxels_;
  std::vector<uint32_t> merged_;    // scratch of the union
  std::vector<uint32_t> unsorted_;  // scratch: a list that came unsorted, sorted
};

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
