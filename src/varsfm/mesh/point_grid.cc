#include "varsfm/mesh/point_grid.h"

#include <algorithm>
#include <cmath>

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

PointCloud VoxelDownsample(const PointCloud& cloud, double voxel_size) {
  if (voxel_size <= 0) return cloud;
  struct Acc {
    Eigen::Vector3d p = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero(),
                    c = Eigen::Vector3d::Zero();
    int count = 0;
    std::vector<uint32_t> views;
  };
  std::unordered_map<uint64_t, size_t> slot;
  std::vector<Acc> acc;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    auto [it, inserted] = slot.try_emplace(Key(CellOf(cloud.points[i], voxel_size)), acc.size());
    if (inserted) acc.emplace_back();
    Acc& a = acc[it->second];
    a.p += cloud.points[i];
    if (cloud.HasNormals()) a.n += cloud.normals[i];
    if (cloud.HasColors()) a.c += cloud.colors[i].cast<double>();
    if (cloud.HasVisibility())
      a.views.insert(a.views.end(), cloud.visibility[i].begin(), cloud.visibility[i].end());
    ++a.count;
  }
  PointCloud out;
  out.viewpoints = cloud.viewpoints;
  for (Acc& a : acc) {
    if (cloud.HasNormals()) {
      // Opposite normals in one voxel (a thin wall) cancel: drop that voxel rather than
      // hand Poisson an arbitrary orientation.
      if (a.n.norm() < 1e-6 * a.count) continue;
      out.normals.push_back(a.n.normalized());
    }
    out.points.push_back(a.p / a.count);
    if (cloud.HasColors()) {
      out.colors.push_back((a.c / a.count).array().round().cast<uint8_t>());
    }
    if (cloud.HasVisibility()) {
      std::sort(a.views.begin(), a.views.end());
      a.views.erase(std::unique(a.views.begin(), a.views.end()), a.views.end());
      out.visibility.push_back(std::move(a.views));
    }
  }
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
