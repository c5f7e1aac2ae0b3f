#pragma once
// Test helper: a Reconstruction holding a synthetic scene (synthetic/synthetic_scene.h) exactly,
// so tests of modules that consume a sparse model can start from known ground truth.
#include <map>
#include <string>
#include <vector>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm::testing {

// Image i of the scene becomes image i + 1 with camera i + 1 (registered, true pose), its 2D
// points are the scene's observations in order (points2D[j] is scene.observations[i][j], so
// outlier flags can be looked up), and every point seen at least twice gets its true position.
inline Reconstruction ReconstructionFromSynthetic(const SyntheticScene& scene) {
  Reconstruction rec;
  std::map<int, std::vector<TrackElement>> tracks;
  for (int i = 0; i < scene.NumImages(); ++i) {
    rec.AddCamera(scene.cameras[i]);
    Image image;
    image.image_id = static_cast<image_t>(i + 1);
    image.camera_id = scene.cameras[i].camera_id;
    image.name = "image" + std::to_string(i);
    image.cam_from_world = scene.poses[i];
    image.registered = true;
    for (const auto& obs : scene.observations[i]) {
      tracks[obs.point_id].push_back(
          {image.image_id, static_cast<point2D_t>(image.points2D.size())});
      image.points2D.push_back({obs.pixel});
    }
    rec.AddImage(image);
  }
  for (const auto& [pid, track] : tracks)
    if (track.size() >= 2) rec.AddPoint3D(scene.points[pid], track);
  return rec;
}

}  // namespace varsfm::testing
