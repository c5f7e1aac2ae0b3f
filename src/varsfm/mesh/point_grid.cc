#include "varsfm/mesh/point_grid.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

using Cell = Eigen::Matrix<int64_t, 3, 1>;

// 64-bit cells, clamped before the conversion: a cloud far from the origin (or a far outlier)
// puts p / size beyond int, whose conversion is undefined. Within int the cells, and so the keys
// below, are what 32-bit cells gave.
Cell CellOf(const Eigen::Vector3d& p, double size) {
  constexpr double kLimit = 4e18;  // below 2^63
  return (p / size).array().floor().max(-kLimit).min(kLimit).cast<int64_t>();
}

// 21 bits per axis: cells wrap around beyond +-1e6 cells, which only merges far-apart buckets
// (queries still compare true distances).
uint64_t Key(const Cell& c) {
  const uint64_t mask = (1u << 21) - 1;
  return ((static_cast<uint64_t>(c.x()) & mask) << 42) |
         ((static_cast<uint64_t>(c.y()) & mask) << 21) | (static_cast<uint64_t>(c.z()) & mask);
}

using CellMap = std::unordered_map<uint64_t, std::vector<size_t>>;

// Calls visit(j) for every point j in cell c and its 26 neighbours, in a fixed order (dx, dy, dz
// each from -1 to 1, a cell's points as inserted): a search over them sees every point within
// one cell size of any point of c.
template <typename Visit>
void ForEachInNeighbourCells(const CellMap& cells, const Cell& c, Visit&& visit) {
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const auto it = cells.find(Key(c + Cell(dx, dy, dz)));
        if (it == cells.end()) continue;
        for (const size_t j : it->second) visit(j);
      }
}

}  // namespace

VoxelMerge::VoxelMerge(double voxel_size, bool normals, bool colors, bool visibility)
    : voxel_size_(voxel_size), normals_(normals), colors_(colors), visibility_(visibility) {
  if (!(voxel_size > 0)) Fail("VoxelMerge: voxel size must be positive");
}

void VoxelMerge::Add(const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                     const Eigen::Matrix<uint8_t, 3, 1>& color,
                     const std::vector<uint32_t>& visibility) {
  auto [it, inserted] = slot_.try_emplace(Key(CellOf(point, voxel_size_)), voxels_.size());
  if (inserted) voxels_.emplace_back();
  Voxel& v = voxels_[it->second];
  v.point += point;
  if (normals_) v.normal += normal;
  if (colors_) v.color += color.cast<double>();
  if (visibility_ && !visibility.empty()) {
    // The union kept as it grows, not after: a voxel of a dense cloud gathers dozens of points
    // seen by the same few views.
    merged_.clear();
    if (std::is_sorted(visibility.begin(), visibility.end())) {
      std::set_union(v.views.begin(), v.views.end(), visibility.begin(), visibility.end(),
                     std::back_inserter(merged_));
    } else {  // a foreign file's lists need not be ascending
      unsorted_.assign(visibility.begin(), visibility.end());
      std::sort(unsorted_.begin(), unsorted_.end());
      std::set_union(v.views.begin(), v.views.end(), unsorted_.begin(), unsorted_.end(),
                     std::back_inserter(merged_));
    }
    merged_.erase(std::unique(merged_.begin(), merged_.end()), merged_.end());
    v.views.swap(merged_);
  }
  ++v.count;
}

PointCloud VoxelMerge::Result() && {
  PointCloud out;
  for (Voxel& v : voxels_) {
    if (normals_) {
      if (v.normal.norm() < 1e-6 * v.count) continue;
      out.normals.push_back(v.normal.normalized());
    }
    out.points.push_back(v.point / v.count);
    if (colors_) out.colors.push_back((v.color / v.count).array().round().cast<uint8_t>());
    if (visibility_) out.visibility.push_back(std::move(v.views));
  }
  voxels_.clear();
  slot_.clear();
  return out;
}

PointCloud VoxelDownsample(const PointCloud& cloud, double voxel_size) {
  if (voxel_size <= 0) return cloud;
  VoxelMerge merge(voxel_size, cloud.HasNormals(), cloud.HasColors(), cloud.HasVisibility());
  static const std::vector<uint32_t> kNone;
  for (size_t i = 0; i < cloud.points.size(); ++i)
    merge.Add(cloud.points[i], cloud.HasNormals() ? cloud.normals[i] : Eigen::Vector3d::Zero(),
              cloud.HasColors() ? cloud.colors[i] : Eigen::Matrix<uint8_t, 3, 1>::Zero(),
              cloud.HasVisibility() ? cloud.visibility[i] : kNone);
  PointCloud out = std::move(merge).Result();
  out.viewpoints = cloud.viewpoints;
  return out;
}

PointCloud VoxelDownsampleAtMost(const PointCloud& cloud, size_t max_points, double voxel_size,
                                 double* used_voxel_size) {
  PointCloud reduced = VoxelDownsample(cloud, voxel_size);
  // An infinite voxel holds every point in one cell: the loop ends for any max_points.
  while (reduced.points.size() > max_points && std::isfinite(voxel_size)) {
    const double ratio =
        static_cast<double>(reduced.points.size()) / std::max<size_t>(max_points, 1);
    voxel_size *= std::max(1.1, 1.02 * std::sqrt(ratio));
    reduced = VoxelDownsample(cloud, voxel_size);
  }
  if (used_voxel_size) *used_voxel_size = voxel_size;
  return reduced;
}

PointGrid::PointGrid(const std::vector<Eigen::Vector3d>& points, double cell_size)
    : points_(points), cell_size_(cell_size) {
  if (cell_size <= 0) Fail("PointGrid: cell size must be positive");
  for (size_t i = 0; i < points.size(); ++i) cells_[Key(CellOf(points[i], cell_size))].push_back(i);
}

std::optional<size_t> PointGrid::NearestWithinCell(const Eigen::Vector3d& query) const {
  const Cell c = CellOf(query, cell_size_);
  double best = cell_size_ * cell_size_;
  std::optional<size_t> nearest;
  ForEachInNeighbourCells(cells_, c, [&](size_t j) {
    const double d = (points_[j] - query).squaredNorm();
    if (d <= best) {
      best = d;
      nearest = j;
    }
  });
  return nearest;
}

}  // namespace varsfm
