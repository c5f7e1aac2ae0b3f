#include "varsfm/sfm/visible_point_counts.h"

namespace varsfm {

void VisiblePointCounts::Recount(const Reconstruction& rec) {
  counts_.clear();
  for (const image_t id : graph_.ImageIds()) {
    Counts& c = counts_[id];
    c.per_point.assign(graph_.NumPoints2D(id), 0);
  }
  for (const auto& [id, image] : rec.images()) {
    if (!image.registered || !graph_.ExistsImage(id)) continue;
    for (point2D_t idx = 0; idx < image.points2D.size(); ++idx)
      if (image.points2D[idx].HasPoint3D()) Update(id, idx, +1);
  }
}

size_t VisiblePointCounts::VisiblePoints(image_t image_id) const {
  const auto it = counts_.find(image_id);
  return it == counts_.end() ? 0 : it->second.visible;
}

void VisiblePointCounts::PointTriangulationChanged(const Image& image, point2D_t idx,
                                                   bool triangulated) {
  if (image.registered && graph_.ExistsImage(image.image_id))
    Update(image.image_id, idx, triangulated ? +1 : -1);
}

void VisiblePointCounts::ImageRegistrationChanged(const Image& image) {
  if (!graph_.ExistsImage(image.image_id)) return;
  for (point2D_t idx = 0; idx < image.points2D.size(); ++idx)
    if (image.points2D[idx].HasPoint3D()) Update(image.image_id, idx, image.registered ? +1 : -1);
}

void VisiblePointCounts::Update(image_t image_id, point2D_t idx, int delta) {
  if (idx >= graph_.NumPoints2D(image_id)) return;
  for (const Correspondence& corr : graph_.CorrespondencesOf(image_id, idx)) {
    Counts& c = counts_.at(corr.image_id);
    uint32_t& n = c.per_point.at(corr.point2D_idx);
    if (delta > 0) {
      if (n++ == 0) ++c.visible;
    } else if (n > 0 && --n == 0) {
      --c.visible;
    }
  }
}

}  // namespace varsfm
