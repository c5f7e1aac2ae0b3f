#include "varsfm/dense/reference_views.h"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

#include "varsfm/dense/source_views.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

std::vector<image_t> SelectReferenceViews(const Reconstruction& rec,
                                          const std::vector<image_t>& candidates,
                                          const ReferenceViewOptions& options) {
  if (options.redundant_fraction <= 0) return candidates;
  std::unordered_map<image_t, size_t> index;
  for (size_t k = 0; k < candidates.size(); ++k) index[candidates[k]] = k;
  // Each candidate's points, and each point's candidate views (its count, kept current).
  std::vector<std::vector<uint32_t>> points_of(candidates.size());
  std::vector<int> views_of_point;
  for (const auto& [id, point] : rec.points3D()) {
    const auto point_index = static_cast<uint32_t>(views_of_point.size());
    int count = 0;
    for (const image_t view : RegisteredViews(rec, point)) {
      const auto it = index.find(view);
      if (it == index.end()) continue;
      points_of[it->second].push_back(point_index);
      ++count;
    }
    views_of_point.push_back(count);
  }
  // Longest mean track first: a view among many others is the likeliest to repeat them. The
  // means are compared as integer cross products, so the order is exact.
  std::vector<uint64_t> track_sum(candidates.size(), 0);
  for (size_t k = 0; k < candidates.size(); ++k)
    for (const uint32_t p : points_of[k]) track_sum[k] += views_of_point[p];
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
  std::vector<bool> keep(candidates.size(), true);
  for (const size_t k : order) {
    const std::vector<uint32_t>& points = points_of[k];
    const auto covered = std::count_if(points.begin(), points.end(), [&](uint32_t p) {
      return views_of_point[p] - 1 >= options.min_other_views;
    });
    if (static_cast<double>(covered) < options.redundant_fraction * points.size()) continue;
    keep[k] = false;
    for (const uint32_t p : points) --views_of_point[p];
  }
  std::vector<image_t> kept;
  for (size_t k = 0; k < candidates.size(); ++k)
    if (keep[k]) kept.push_back(candidates[k]);
  return kept;
}

void ReferenceViewOptions::Check() const {
  CheckInRange("--dense-redundant-fraction", redundant_fraction, 0.0, 1.0);
  CheckInRange("--dense-redundant-other-views", min_other_views, 2, 1000);
}

}  // namespace varsfm
