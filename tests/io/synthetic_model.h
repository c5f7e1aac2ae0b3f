#pragma once
// Test helper: a Reconstruction holding a synthetic scene exactly (every point seen twice or
// more, with its full track), with colours and point errors filled so writers have data to lose.
#include <map>
#include <string>
#include <vector>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm::testing {

inline Reconstruction ReconstructionFromSynthetic(const SyntheticScene& scene) {
  Reconstruction rec;
  std::map<int, std::vector<TrackElement>> tracks;
  for (int i = 0; i < scene.NumImages(); ++i) {
    rec.AddCamera(scene.cameras[i]);
    Image image;
    image.image_id = i + 1;
    image.camera_id = scene.cameras[i].camera_id;
    image.name = "image" + std::to_string(i) + ".jpg";
    image.cam_from_world = scene.poses[i];
    image.registered = true;
    for (const auto& obs : scene.observations[i]) {
      tracks[obs.point_id].push_back(
          {image.image_id, static_cast<point2D_t>(image.points2D.size())});
      image.points2D.push_back({obs.pixel});
    }
    rec.AddImage(image);
  }
  for (const auto& [pid, track] : tracks) {
    if (track.size() < 2) continue;
    const Eigen::Matrix<uint8_t, 3, 1> color(pid % 256, (7 * pid) % 256, (13 * pid) % 256);
    rec.AddPoint3D(scene.points[pid], track, color);
  }
  rec.UpdatePointErrors();
  return rec;
}

}  // namespace varsfm::testing
