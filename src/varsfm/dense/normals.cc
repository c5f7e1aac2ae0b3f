#include "varsfm/dense/normals.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

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

}  // namespace

std::vector<Eigen::Vector3d> EstimateNormals(const std::vector<Eigen::Vector3d>& points,
                                             const std::vector<Eigen::Vector3d>& view_centers,
                                             int k, double spacing) {
  const size_t n = points.size();
  std::vector<Eigen::Vector3d> normals(n);
  if (n == 0) return normals;
  const double cell = std::max(std::max(2.0, std::sqrt(static_cast<double>(k))) * spacing, 1e-12);
  const auto cell_of = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3<int64_t>(static_cast<int64_t>(std::floor(p.x() / cell)),
                                   static_cast<int64_t>(std::floor(p.y() / cell)),
                                   static_cast<int64_t>(std::floor(p.z() / cell)));
  };
  // Points sorted by cell key: a cell's points are one contiguous range.
  std::vector<std::pair<uint64_t, uint32_t>> keyed(n);
  for (size_t i = 0; i < n; ++i) {
    const auto c = cell_of(points[i]);
    keyed[i] = {CellKey(c.x(), c.y(), c.z()), static_cast<uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());

  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const auto& range) {
    std::vector<std::pair<double, uint32_t>> near;
    for (size_t i = range.begin(); i < range.end(); ++i) {
      const Eigen::Vector3d& p = points[i];
      const auto c = cell_of(p);
      near.clear();
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const uint64_t key = CellKey(c.x() + dx, c.y() + dy, c.z() + dz);
            auto it = std::lower_bound(keyed.begin(), keyed.end(), std::make_pair(key, 0u));
            for (; it != keyed.end() && it->first == key; ++it)
              near.push_back({(points[it->second] - p).squaredNorm(), it->second});
          }
      const size_t m = std::min(near.size(), static_cast<size_t>(k) + 1);  // + the point itself
      std::partial_sort(near.begin(), near.begin() + m, near.end());
      Eigen::Vector3d normal = (view_centers[i] - p).normalized();
      if (m >= 4) {
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
        if (axis.allFinite()) normal = axis.dot(view_centers[i] - p) < 0 ? -axis : axis;
      }
      normals[i] = normal;
    }
  });
  return normals;
}

}  // namespace varsfm
