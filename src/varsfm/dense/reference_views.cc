#include "varsfm/dense/reference_views.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>

#include "varsfm/dense/source_views.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

std::vector<image_t> SelectReferenceViews(const Reconstruction& rec,
                                          const std::vector<image_t>& candidates,
                                          const ReferenceViewOptions& options,
                                          int min_fused_views) {
  if (options.redundant_fraction <= 0) return candidates;
  std::unordered_map<image_t, size_t> index;
  std::vector<Eigen::Vector3d> centres;
  for (size_t k = 0; k < candidates.size(); ++k) {
    index[candidates[k]] = k;
    centres.push_back(rec.image(candidates[k]).Center());
  }
  // Each point's candidate views with the unit ray from each, and each candidate's points as
  // (point, position in the point's views).
  struct PointView {
    uint32_t view;
    Eigen::Vector3f ray;
  };
  std::vector<std::vector<PointView>> views_of;
  std::vector<std::vector<std::pair<uint32_t, uint32_t>>> points_of(candidates.size());
  for (const auto& [id, point] : rec.points3D()) {
    const auto p = static_cast<uint32_t>(views_of.size());
    std::vector<PointView> views;
    for (const image_t view : RegisteredViews(rec, point)) {
      const auto it = index.find(view);
      if (it == index.end()) continue;
      const auto k = static_cast<uint32_t>(it->second);
      points_of[k].push_back({p, static_cast<uint32_t>(views.size())});
      views.push_back({k, (point.xyz - centres[k]).normalized().cast<float>()});
    }
    views_of.push_back(std::move(views));
  }
  // Longest mean track first: a view among many others is the likeliest to repeat them. The
  // means are compared as integer cross products, so the order is exact.
  std::vector<uint64_t> track_sum(candidates.size(), 0);
  for (size_t k = 0; k < candidates.size(); ++k)
    for (const auto& [p, at] : points_of[k]) track_sum[k] += views_of[p].size();
  // A view without sparse points is kept, and left out of the order (its mean is undefined).
  std::vector<size_t> order;
  for (size_t k = 0; k < candidates.size(); ++k)
    if (!points_of[k].empty()) order.push_back(k);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const uint64_t left = track_sum[a] * points_of[b].size();
    const uint64_t right = track_sum[b] * points_of[a].size();
    if (left != right) return left > right;
    return candidates[a] < candidates[b];
  });
  const auto min_cos =
      static_cast<float>(std::cos(options.max_view_angle_deg * std::numbers::pi / 180.0));
  std::vector<bool> keep(candidates.size(), true);
  for (const size_t k : order) {
    const auto& points = points_of[k];
    // A point is covered by the other kept views that see it from within the angle, and
    // uncovered without k when the kept views, k among them, are just as many as fusion needs.
    size_t covered = 0, uncovered = 0;
    for (const auto& [p, at] : points) {
      const Eigen::Vector3f& ray = views_of[p][at].ray;
      int others = 0, others_near = 0;
      for (const PointView& other : views_of[p]) {
        if (other.view == k || !keep[other.view]) continue;
        ++others;
        if (other.ray.dot(ray) >= min_cos) ++others_near;
      }
      if (others_near >= options.min_other_views) ++covered;
      if (others + 1 == min_fused_views) ++uncovered;
    }
    if (static_cast<double>(covered) < options.redundant_fraction * points.size()) continue;
    if (static_cast<double>(uncovered) > options.max_uncovered_fraction * points.size()) continue;
    keep[k] = false;
  }
  std::vector<image_t> kept;
  for (size_t k = 0; k < candidates.size(); ++k)
    if (keep[k]) kept.push_back(candidates[k]);
  return kept;
}

void ReferenceViewOptions::Check() const {
  CheckInRange("--dense-redundant-fraction", redundant_fraction, 0.0, 1.0);
  CheckInRange("--dense-redundant-other-views", min_other_views, 2, 1000);
  CheckInRange("--dense-redundant-max-uncovered", max_uncovered_fraction, 0.0, 1.0);
  CheckInRange("--dense-redundant-max-angle", max_view_angle_deg, 0.0, 180.0);
}

}  // namespace varsfm
