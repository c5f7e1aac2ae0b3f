#include "varsfm/dense/normals.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>

namespace varsfm {
namespace {

// 21 bits per axis packed in one key; cells far apart may alias, which only adds candidates
// that the distance sort then rejects.
uint64_t CellKey(int64_t x, int64_t y, int64_t z) {
  constexpr uint64_t kMask = (1u << 21) - 1;
  return ((static_cast<uint64_t>(x) & kMask) << 42) | ((static_cast<uint64_t>(y) & kMask) << 21) |
         (static_cast<uint64_t>(z) & kMask);
}

// The smallest principal axis of the first m of `near` (PCA of the neighbourhood), oriented
// towards the camera centre; the direction to the camera when m < 4 or the fit fails.
Eigen::Vector3d Normal(const std::vector<Eigen::Vector3d>& points,
                       const std::vector<std::pair<double, uint32_t>>& near, size_t m,
                       const Eigen::Vector3d& p, const Eigen::Vector3d& camera) {
  Eigen::Vector3d normal = (camera - p).normalized();
  if (m < 4) return normal;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (size_t j = 0; j < m; ++j) mean += points[near[j].second];
  mean /= static_cast<double>(m);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t j = 0; j < m; ++j) {
    const Eigen::Vector3d d = points[near[j].second] - mean;
    cov += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(cov);
  const Eigen::Vector3d axis = eig.eigenvectors().col(0);  // smallest eigenvalue
  if (axis.allFinite()) normal = axis.dot(camera - p) < 0 ? -axis : axis;
  return normal;
}

// Points sorted by the key of their grid cell, so that each cell is one contiguous range.
struct CellIndex {
  std::vector<std::pair<uint64_t, uint32_t>> keyed;  // (cell key, point), sorted
  std::vector<uint64_t> keys;                        // distinct keys, sorted
  std::vector<size_t> starts;                        // cell c: keyed[starts[c], starts[c + 1])

  CellIndex(const std::vector<Eigen::Vector3d>& points, double cell) : keyed(points.size()) {
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector3d c = (points[i] / cell).array().floor();
      keyed[i] = {CellKey(static_cast<int64_t>(c.x()), static_cast<int64_t>(c.y()),
                          static_cast<int64_t>(c.z())),
                  static_cast<uint32_t>(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    for (size_t i = 0; i < keyed.size(); ++i)
      if (i == 0 || keyed[i].first != keyed[i - 1].first) {
        keys.push_back(keyed[i].first);
        starts.push_back(i);
      }
    starts.push_back(keyed.size());
  }
  // Mean over points of the number of points sharing their cell.
  double Occupancy() const {
    double sum = 0;
    for (size_t c = 0; c + 1 < starts.size(); ++c) {
      const double m = static_cast<double>(starts[c + 1] - starts[c]);
      sum += m * m;
    }
    return sum / static_cast<double>(keyed.size());
  }
};

}  // namespace

std::vector<Eigen::Vector3d> EstimateNormals(const std::vector<Eigen::Vector3d>& points,
                                             const std::vector<Eigen::Vector3d>& view_centers,
                                             int k, double spacing) {
  const size_t n = points.size();
  std::vector<Eigen::Vector3d> normals(n);
  if (n == 0) return normals;
  double cell = std::max(std::max(2.0, std::sqrt(static_cast<double>(k))) * spacing, 1e-12);
  // Clouds fused from overlapping pairs sample a surface more densely than one point per pixel
  // footprint, so the 27 cells around a point can hold thousands of points. Shrink the cell
  // (as the square root: points lie on surfaces) until a cell holds about k / 2 points, so
  // the 27 cells still hold several times k candidates but not many more.
  std::optional<CellIndex> index(std::in_place, points, cell);
  const double occupancy = index->Occupancy(), target = std::max(2.0, 0.5 * k);
  if (occupancy > 2 * target) {
    cell *= std::max(0.125, std::sqrt(target / occupancy));
    index.emplace(points, cell);
  }
  const CellIndex& grid = *index;

  // One task per block of cells: the candidates of the 27 cells around a cell are gathered
  // once for all the points in it.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, grid.keys.size(), 256), [&](const auto& range) {
    std::vector<uint32_t> candidates;
    std::vector<std::pair<double, uint32_t>> near;
    for (size_t c = range.begin(); c < range.end(); ++c) {
      const Eigen::Vector3d centre =
          (points[grid.keyed[grid.starts[c]].second] / cell).array().floor();
      const auto cx = static_cast<int64_t>(centre.x()), cy = static_cast<int64_t>(centre.y()),
                 cz = static_cast<int64_t>(centre.z());
      candidates.clear();
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const uint64_t key = CellKey(cx + dx, cy + dy, cz + dz);
            const auto it = std::lower_bound(grid.keys.begin(), grid.keys.end(), key);
            if (it == grid.keys.end() || *it != key) continue;
            const size_t d = static_cast<size_t>(it - grid.keys.begin());
            for (size_t j = grid.starts[d]; j < grid.starts[d + 1]; ++j)
              candidates.push_back(grid.keyed[j].second);
          }
      for (size_t j = grid.starts[c]; j < grid.starts[c + 1]; ++j) {
        const uint32_t i = grid.keyed[j].second;
        const Eigen::Vector3d& p = points[i];
        near.clear();
        for (uint32_t q : candidates) near.push_back({(points[q] - p).squaredNorm(), q});
        const size_t m = std::min(near.size(), static_cast<size_t>(k) + 1);  // + the point
        // The k + 1 nearest as a set (ties broken by index, so the set is unique).
        std::nth_element(near.begin(), near.begin() + (m - 1), near.end());
        normals[i] = Normal(points, near, m, p, view_centers[i]);
      }
    }
  });
  return normals;
}

}  // namespace varsfm
