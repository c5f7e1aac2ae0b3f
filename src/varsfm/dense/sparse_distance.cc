#include "varsfm/dense/sparse_distance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>

#include "varsfm/util/error.h"
#include "varsfm/util/statistics.h"

namespace varsfm {
namespace {

// k-nearest-neighbour search over a few thousand sparse points by a hashed uniform grid:
// cubic shells of cells around the query are visited in growing Chebyshev radius until the
// k-th best distance is within the radius already covered (nothing farther can beat it).
class SparseGrid {
 public:
  SparseGrid(const std::vector<Eigen::Vector3d>& points, double cell)
      : points_(points), cell_(cell) {
    for (uint32_t i = 0; i < points.size(); ++i) cells_[Key(CellOf(points[i]))].push_back(i);
  }

  // Indices of up to k nearest points, nearest first; fewer when none lies within
  // kMaxShells cells.
  double Reach() const { return static_cast<double>(kMaxShells) * cell_; }

  std::vector<uint32_t> Nearest(const Eigen::Vector3d& q, int k) const {
    std::vector<std::pair<double, uint32_t>> best;  // (squared distance, index), sorted
    const Eigen::Vector3<int64_t> c = CellOf(q);
    for (int64_t rho = 0; rho <= kMaxShells; ++rho) {
      for (int64_t dz = -rho; dz <= rho; ++dz)
        for (int64_t dy = -rho; dy <= rho; ++dy)
          for (int64_t dx = -rho; dx <= rho; ++dx) {
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != rho) continue;
            const auto it = cells_.find(Key({c.x() + dx, c.y() + dy, c.z() + dz}));
            if (it == cells_.end()) continue;
            for (uint32_t i : it->second) best.push_back({(points_[i] - q).squaredNorm(), i});
          }
      std::sort(best.begin(), best.end());
      if (best.size() > static_cast<size_t>(k)) best.resize(k);
      // Points outside the shells visited are at least rho cells away.
      const double covered = static_cast<double>(rho) * cell_;
      if (best.size() == static_cast<size_t>(k) && best.back().first <= covered * covered) break;
    }
    std::vector<uint32_t> out;
    for (const auto& b : best) out.push_back(b.second);
    return out;
  }

 private:
  static constexpr int64_t kMaxShells = 16;
  Eigen::Vector3<int64_t> CellOf(const Eigen::Vector3d& p) const {
    return {static_cast<int64_t>(std::floor(p.x() / cell_)),
            static_cast<int64_t>(std::floor(p.y() / cell_)),
            static_cast<int64_t>(std::floor(p.z() / cell_))};
  }
  static uint64_t Key(const Eigen::Vector3<int64_t>& c) {
    constexpr uint64_t kMask = (1u << 21) - 1;
    return ((static_cast<uint64_t>(c.x()) & kMask) << 42) |
           ((static_cast<uint64_t>(c.y()) & kMask) << 21) | (static_cast<uint64_t>(c.z()) & kMask);
  }
  const std::vector<Eigen::Vector3d>& points_;
  double cell_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

}  // namespace

SparseDistanceStats MeasureAgainstSparse(const std::vector<Eigen::Vector3d>& dense,
                                         const Reconstruction& rec, int k, size_t max_checked) {
  std::vector<Eigen::Vector3d> sparse;
  std::vector<double> depths;
  for (const auto& [id, point] : rec.points3D()) {
    sparse.push_back(point.xyz);
    for (const TrackElement& el : point.track)
      if (rec.ExistsImage(el.image_id) && rec.image(el.image_id).registered)
        depths.push_back((rec.image(el.image_id).cam_from_world * point.xyz).z());
  }
  if (sparse.size() < static_cast<size_t>(std::max(k, 1)))
    Fail("dense check: the sparse model has {} points, {} needed", sparse.size(), k);
  if (dense.empty()) Fail("dense check: the dense cloud is empty");
  SparseDistanceStats stats;
  stats.scene_depth = Median(depths);
  if (!(stats.scene_depth > 0)) Fail("dense check: the sparse points have no positive depth");

  // Cell size: sparse points sample surfaces, so share the area spanned by the two largest
  // robust extents (5th..95th percentile per axis) out among them, about four points per cell
  // (so the k nearest are usually found within the first shell of cells).
  std::array<double, 3> extent;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> v;
    for (const auto& p : sparse) v.push_back(p[a]);
    std::sort(v.begin(), v.end());
    extent[a] = v[v.size() * 95 / 100] - v[v.size() * 5 / 100];
  }
  std::sort(extent.begin(), extent.end());
  const double cell = std::max(2 * std::sqrt(extent[2] * extent[1] / sparse.size()), 1e-9);
  const SparseGrid grid(sparse, cell);

  const size_t step = std::max<size_t>(1, (dense.size() + max_checked - 1) / max_checked);
  const size_t n = (dense.size() + step - 1) / step;
  std::vector<double> nearest(n, -1), plane(n, -1);
  tbb::parallel_for(size_t{0}, n, [&](size_t i) {
    const Eigen::Vector3d& q = dense[i * step];
    const std::vector<uint32_t> near = grid.Nearest(q, k);
    // Nothing within the search reach: far from the model; its reach is a lower bound.
    nearest[i] = near.empty() ? grid.Reach() : (sparse[near[0]] - q).norm();
    if (near.size() < 3) {
      plane[i] = grid.Reach();
      return;
    }
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (uint32_t j : near) mean += sparse[j];
    mean /= static_cast<double>(near.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (uint32_t j : near) cov += (sparse[j] - mean) * (sparse[j] - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(cov);
    plane[i] = std::abs(eig.eigenvectors().col(0).dot(q - mean));  // smallest axis: the normal
  });
  std::vector<double> nearest_ok, plane_ok;
  size_t within = 0;
  for (size_t i = 0; i < n; ++i) {
    if (nearest[i] >= 0) nearest_ok.push_back(nearest[i] / stats.scene_depth);
    if (plane[i] >= 0) {
      plane_ok.push_back(plane[i] / stats.scene_depth);
      within += plane_ok.back() < 0.01;
    }
  }
  stats.num_checked = n;
  stats.median_nearest = Median(nearest_ok);
  stats.median_plane = Median(plane_ok);
  stats.fraction_within_1pc = plane_ok.empty() ? 0 : static_cast<double>(within) / plane_ok.size();
  return stats;
}

}  // namespace varsfm
