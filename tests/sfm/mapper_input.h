#pragma once
// The mapper's input made from synthetic scenes, for the tests of the mapper and its driver.
#include <map>
#include <string>
#include <vector>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/sfm/correspondence_graph.h"
#include "varsfm/synthetic/synthetic_scene.h"

namespace varsfm::testing {

struct MapperInput {
  Reconstruction reconstruction;
  CorrespondenceGraph graph;
};

// Adds the images of `scene` as image ids `ids` (one per image of the scene), each unregistered
// with a camera of its own at the usual prior (1.2 max(w, h), centred principal point), and
// correspondences between every pair of them from the points they both see. Nothing links them
// to the images already in `in`: several scenes added to one input are unconnected.
inline void AddScene(const SyntheticScene& scene, const std::vector<image_t>& ids,
                     const std::string& name_prefix, MapperInput* in) {
  for (int i = 0; i < scene.NumImages(); ++i) {
    const Camera& truth = scene.cameras[i];
    Camera camera =
        Camera::FromFocal(truth.width, truth.height, 1.2 * std::max(truth.width, truth.height));
    camera.camera_id = ids[i];
    in->reconstruction.AddCamera(camera);
    Image image;
    image.image_id = ids[i];
    image.camera_id = camera.camera_id;
    image.name = name_prefix + std::to_string(i);
    for (const auto& obs : scene.observations[i]) image.points2D.push_back({obs.pixel});
    in->graph.AddImage(image.image_id, image.points2D.size());
    in->reconstruction.AddImage(image);
  }
  for (int i = 0; i < scene.NumImages(); ++i) {
    std::map<int, point2D_t> index_of_point;
    for (point2D_t k = 0; k < scene.observations[i].size(); ++k)
      index_of_point[scene.observations[i][k].point_id] = k;
    for (int j = i + 1; j < scene.NumImages(); ++j) {
      FeatureMatches matches;
      for (point2D_t k = 0; k < scene.observations[j].size(); ++k) {
        const auto it = index_of_point.find(scene.observations[j][k].point_id);
        if (it != index_of_point.end()) matches.push_back({it->second, k});
      }
      in->graph.AddImagePair(ids[i], ids[j], matches);
    }
  }
}

// One scene as image ids 1, 2, ... named image0, image1, ...
inline MapperInput MakeInput(const SyntheticScene& scene) {
  MapperInput in;
  std::vector<image_t> ids;
  for (int i = 0; i < scene.NumImages(); ++i) ids.push_back(static_cast<image_t>(i + 1));
  AddScene(scene, ids, "image", &in);
  return in;
}

}  // namespace varsfm::testing
