#pragma once
// Test helper: a synthetic scene as a model with data for writers to lose: the exact
// reconstruction of tests/support/synthetic_reconstruction.h, with file-like image names,
// colours and point errors filled in.
#include <string>

#include "support/synthetic_reconstruction.h"

namespace varsfm::testing {

inline Reconstruction ModelFromSynthetic(const SyntheticScene& scene) {
  Reconstruction rec = ReconstructionFromSynthetic(scene);
  for (int i = 0; i < scene.NumImages(); ++i)
    rec.image(static_cast<image_t>(i + 1)).name = "image" + std::to_string(i) + ".jpg";
  for (auto& [id, point] : rec.points3D()) {
    // points2D[j] of image i + 1 is scene.observations[i][j] (support helper's contract).
    const TrackElement& el = point.track.front();
    const int pid = scene.observations[el.image_id - 1][el.point2D_idx].point_id;
    point.color = Eigen::Matrix<uint8_t, 3, 1>(pid % 256, (7 * pid) % 256, (13 * pid) % 256);
  }
  rec.UpdatePointErrors();
  return rec;
}

}  // namespace varsfm::testing
