#include "varsfm/synthetic/synthetic_reconstruction.h"

#include <map>
#include <string>
#include <vector>

namespace varsfm {

Reconstruction ReconstructionFromSynthetic(const SyntheticScene& scene) {
  Reconstruction rec;
  std::map<int, std::vector<TrackElement>> tracks;
  for (int i = 0; i < scene.NumImages(); ++i) {
    Image& image = AddTrueImage(i, scene.cameras[i], scene.poses[i], &rec);
    for (const auto& obs : scene.observations[i]) {
      tracks[obs.point_id].push_back(
          {image.image_id, static_cast<point2D_t>(image.points2D.size())});
      image.points2D.push_back({obs.pixel});
    }
  }
  for (const auto& [pid, track] : tracks)
    if (track.size() >= 2) rec.AddPoint3D(scene.points[pid], track);
  return rec;
}

Image& AddTrueImage(int index, const Camera& camera, const Rigid3d& cam_from_world,
                    Reconstruction* rec) {
  rec->AddCamera(camera);
  Image image;
  image.image_id = static_cast<image_t>(index + 1);
  image.camera_id = camera.camera_id;
  image.name = "image" + std::to_string(index);
  image.cam_from_world = cam_from_world;
  image.registered = true;
  rec->AddImage(image);
  return rec->image(image.image_id);
}

}  // namespace varsfm
