#include "varsfm/ba/intrinsics_groups.h"

#include <algorithm>
#include <limits>

namespace varsfm {

unsigned SharedIntrinsicsMask(const IntrinsicsOptions& options) {
  unsigned mask = 0;
  for (const int i : options.shared_per_size)
    if (i >= 0 && i < Camera::kNumParams) mask |= 1u << i;
  return mask;
}

std::vector<int> ZoomBandGroups(const std::vector<std::pair<double, camera_t>>& by_focal,
                                const std::map<camera_t, int>& images_of_camera, double max_ratio,
                                int min_images) {
  struct Band {
    size_t first, end;  // [first, end) of by_focal
    int images;
  };
  std::vector<Band> bands;
  int total = 0, large = 0;
  for (size_t first = 0; first < by_focal.size();) {
    Band band{first, first + 1, images_of_camera.at(by_focal[first].second)};
    while (band.end < by_focal.size() &&
           (max_ratio <= 0.0 || by_focal[band.end].first <= max_ratio * by_focal[first].first))
      band.images += images_of_camera.at(by_focal[band.end++].second);
    bands.push_back(band);
    total += band.images;
    large += band.images >= min_images;
    first = band.end;
  }
  if (total < min_images) return {};
  std::vector<int> group_of(by_focal.size(), 0);
  for (size_t b = 0; b < bands.size(); ++b) {
    size_t group = b;
    if (large == 0) {
      group = 0;
    } else if (bands[b].images < min_images) {
      double nearest = std::numeric_limits<double>::infinity();
      for (size_t o = 0; o < bands.size(); ++o) {
        if (bands[o].images < min_images) continue;
        const double ratio =
            o < b ? by_focal[bands[b].first].first / by_focal[bands[o].end - 1].first
                  : by_focal[bands[o].first].first / by_focal[bands[b].end - 1].first;
        if (ratio < nearest) nearest = ratio, group = o;
      }
    }
    std::fill(group_of.begin() + bands[b].first, group_of.begin() + bands[b].end,
              static_cast<int>(group));
  }
  return group_of;
}

std::map<camera_t, IntrinsicsGroupKey> SharedGroupMembers(
    const IntrinsicsOptions& options, const std::set<camera_t>& constant_cameras,
    const std::set<image_t>& images, const Reconstruction& rec) {
  std::map<camera_t, IntrinsicsGroupKey> members;
  if (SharedIntrinsicsMask(options) == 0) return members;
  std::map<std::pair<int, int>, std::map<camera_t, int>> images_of_camera;  // per size
  for (const image_t image_id : images) {
    const camera_t id = rec.image(image_id).camera_id;
    if (constant_cameras.count(id)) continue;
    ++images_of_camera[{rec.camera(id).width, rec.camera(id).height}][id];
  }
  for (const auto& [size, counts] : images_of_camera) {
    std::vector<std::pair<double, camera_t>> by_focal;
    for (const auto& [id, count] : counts) by_focal.emplace_back(rec.camera(id).focal(), id);
    std::sort(by_focal.begin(), by_focal.end());
    const std::vector<int> groups = ZoomBandGroups(by_focal, counts, options.max_shared_focal_ratio,
                                                   std::max(1, options.min_images_to_share));
    for (size_t i = 0; i < groups.size(); ++i)
      members[by_focal[i].second] = {size.first, size.second, groups[i]};
  }
  return members;
}

}  // namespace varsfm
