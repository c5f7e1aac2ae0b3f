#pragma once
// A point cloud too large to hold, read merged: each voxel's points become one as they are read
// (VoxelMerge, point_grid.h), the voxel chosen so that at most a given number remain. A thousand
// photos at 800 px make tens of millions of dense points, whose whole cloud the mesh stage would
// hold at about 256 bytes a point (pipeline/mesh.h) before merging them anyway.
#include <cstddef>
#include <filesystem>

#include "varsfm/io/point_visibility.h"
#include "varsfm/scene/point_cloud.h"

namespace varsfm {

// However large the voxel, a cloud around the origin keeps a point in each of the eight voxels
// that meet there.
inline constexpr size_t kMinMergedReadPoints = 8;

struct MergedRead {
  // The merged points: normals and colours where the file has them, and its own visibility (its
  // viewpoints with it) when it holds one and no `visibility_file` is given.
  PointCloud cloud;
  // Per merged point, the union of the image ids that `visibility_file` gives its points (empty
  // without one).
  PointVisibility image_ids;
  size_t file_points = 0;  // vertices in the file
  double voxel = 0;        // edge of the merge voxel
  int passes = 0;          // reads of the whole file, the first (the spacing's sample) included
};

// Reads `file` (a PLY point cloud, io/ply.h) and, where `visibility_file` is not empty, the
// image ids beside it (io/point_visibility.h), merged at the smallest voxel tried that leaves at
// most `max_points` points, at least kMinMergedReadPoints. The first voxel tried comes from the
// spacing of an even sample of the points, scaled to the whole cloud as points on a surface are
// (spacing ~ 1 / sqrt(count)); a pass that would exceed max_points stops and the voxel grows by
// the square root of the overshoot it projects. The cap bounds the memory: the points that
// remain may be fewer. Throws varsfm::Error as ReadPly and ReadPointVisibility do, when the two
// files' counts differ, and for a max_points below kMinMergedReadPoints.
MergedRead ReadMerged(const std::filesystem::path& file,
                      const std::filesystem::path& visibility_file, size_t max_points);

}  // namespace varsfm
