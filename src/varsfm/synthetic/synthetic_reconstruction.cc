#include "varsfm/synthetic/synthetic_reconstruction.h"

#include <map>
#include <string>
#include <vector>

namespace varsfm {

Reconstruction ReconstructionFromSynthetic(const SyntheticScene& scene) {
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

}  // namespace varsfm
