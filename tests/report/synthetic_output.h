#pragma once
// A run's output folder made from a synthetic scene with exact truth, for the report's tests:
// OUT/sparse (or sparse/0) with every image but the last registered, summary.json, a workspace
// with the images, their keypoints and the pairs' inlier counts (the last image only weakly
// matched), the photos (flat colours, no red) and, optionally, model.glb: a red textured box
// around the scene, so that a screenshot can tell the model from the cameras and points.
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <opencv2/core.hpp>

#include "varsfm/image/image_file.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/io/database.h"
#include "varsfm/pipeline/map_summary.h"
#include "varsfm/synthetic/synthetic_reconstruction.h"
#include "varsfm/texture/gltf_writer.h"

namespace varsfm::testing {

struct SyntheticOutputOptions {
  bool model_in_subfolder = false;  // OUT/sparse/0 instead of OUT/sparse
  bool with_glb = true;
  int num_images = 6;
};

inline SyntheticScene ReportScene(int num_images) {
  SyntheticOptions options;
  options.num_images = num_images;
  options.num_points = 400;
  options.width = 320;
  options.height = 240;
  options.focal_start = 300;  // a zoom sweep: x1.0 to x1.5
  options.focal_end = 450;
  options.k1 = -0.05;
  return GenerateSyntheticScene(options);
}

// A red box of side 2 around the origin (the synthetic points' cube), each face one quad.
inline TexturedMesh RedBox() {
  TexturedMesh mesh;
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y)
      for (int z = 0; z < 2; ++z) mesh.vertices.emplace_back(2.0 * x - 1, 2.0 * y - 1, 2.0 * z - 1);
  mesh.texcoords = {{0.1f, 0.1f}, {0.9f, 0.1f}, {0.9f, 0.9f}, {0.1f, 0.9f}};
  // Faces of the cube by vertex index x*4 + y*2 + z.
  const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& q : quads) {
    mesh.faces.emplace_back(q[0], q[1], q[2]);
    mesh.faces.emplace_back(q[0], q[2], q[3]);
    mesh.face_texcoords.emplace_back(0, 1, 2);
    mesh.face_texcoords.emplace_back(0, 2, 3);
    mesh.face_page.insert(mesh.face_page.end(), 2, 0);
  }
  mesh.pages.push_back(cv::Mat(100, 60, CV_8UC3, cv::Scalar(20, 20, 230)));  // BGR: red
  return mesh;
}

// Writes the folder and returns the model as written.
inline Reconstruction WriteSyntheticOutput(const std::filesystem::path& out,
                                           const SyntheticOutputOptions& options = {}) {
  const SyntheticScene scene = ReportScene(options.num_images);
  Reconstruction model = ReconstructionFromSynthetic(scene);
  const image_t unregistered = static_cast<image_t>(options.num_images);
  model.DeRegisterImage(unregistered);
  std::filesystem::create_directories(out / "images");
  Database db(out / "workspace.db");
  for (const auto& [id, image] : model.images()) {
    model.image(id).name = fmt::format("photo_{:02}.png", id);
    const Camera& camera = model.camera(image.camera_id);
    const camera_t camera_id = db.WriteCamera({.model_id = 0,
                                               .width = camera.width,
                                               .height = camera.height,
                                               .params = {camera.focal(), 160, 120}});
    db.WriteImage({.name = model.image(id).name, .camera_id = camera_id});
    db.WriteKeypoints(id, FeatureKeypoints(image.points2D.size(), FeatureKeypoint(1, 1)));
    // Flat blue-green photos: no red, which marks the textured model in screenshots.
    WriteImage(out / "images" / model.image(id).name,
               cv::Mat(camera.height, camera.width, CV_8UC3, cv::Scalar(200, 120 + 20 * id, 40)));
  }
  // Pairs: consecutive and next-but-one images, 100 inliers; the unregistered image's only 5.
  for (image_t a = 1; a <= unregistered; ++a)
    for (image_t b = a + 1; b <= std::min<image_t>(a + 2, unregistered); ++b) {
      TwoViewGeometry tvg;
      tvg.config = TwoViewGeometry::kUncalibrated;
      tvg.inlier_matches.assign(b == unregistered ? 5 : 100, FeatureMatch{0, 0});
      db.WriteTwoViewGeometry(a, b, tvg);
    }
  const auto sparse = options.model_in_subfolder ? out / "sparse" / "0" : out / "sparse";
  WriteColmapModel(model, sparse, {.binary = true});
  nlohmann::json summary = ReconstructionSummaryJson(model);
  summary["seconds"] = {{"extract", 1.5}, {"match", 2.0}, {"map", 3.0}, {"local_ba", 1.0}};
  summary["initial_pair"] = {1, 3};
  summary["initial_calibration_degenerate"] = false;
  summary["image_dir"] = std::filesystem::absolute(out / "images").string();
  std::ofstream(out / "summary.json") << summary.dump(2);
  if (options.with_glb) WriteGlb(out / "model.glb", RedBox());
  return model;
}

}  // namespace varsfm::testing
