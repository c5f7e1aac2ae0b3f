#pragma once
// A zooming, distorting synthetic capture with photos rendered from a smooth pattern on the
// viewing ray, so undistorted pixels can be checked against the exact colour of their ray.
#include <cmath>
#include <filesystem>

#include <opencv2/core.hpp>

#include "varsfm/image/image_file.h"
#include "varsfm/synthetic/synthetic_reconstruction.h"

namespace varsfm::testing {

// Grey level of the ray through normalised coordinates n: smooth (a few pixels per period at
// these focal lengths), so bilinear resampling errs by a grey level or two at most.
inline double RayPattern(const Eigen::Vector2d& n) {
  return 128.0 + 90.0 * std::sin(9.0 * n.x()) * std::cos(7.0 * n.y());
}

inline SyntheticOptions ZoomingDistortedCapture() {
  SyntheticOptions options;
  options.num_images = 4;
  options.num_points = 300;
  options.width = 320;
  options.height = 240;
  options.focal_start = 300;
  options.focal_end = 420;
  options.k1 = -0.12;
  options.k2 = 0.03;
  options.principal_point_offset = 6;
  return options;
}

// The capture as a sparse model whose image names are PNG files.
inline Reconstruction ZoomingModel(const SyntheticOptions& options = ZoomingDistortedCapture()) {
  Reconstruction model = ReconstructionFromSynthetic(GenerateSyntheticScene(options));
  for (const auto& [id, image] : model.images()) model.image(id).name = image.name + ".png";
  return model;
}

// The photo `camera` takes of the ray pattern, BGR.
inline cv::Mat RenderRayPattern(const Camera& camera) {
  cv::Mat image(camera.height, camera.width, CV_8UC3);
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const double g = RayPattern(camera.ImageToNormalized({x + 0.5, y + 0.5}));
      const auto v = static_cast<uint8_t>(std::lround(g));
      image.at<cv::Vec3b>(y, x) = {v, v, v};
    }
  }
  return image;
}

// Writes each registered image's photo as image_dir/<name>.
inline void WritePhotos(const Reconstruction& model, const std::filesystem::path& image_dir) {
  std::filesystem::create_directories(image_dir);
  for (const auto& [id, image] : model.images()) {
    WriteImage(image_dir / image.name, RenderRayPattern(model.CameraOf(id)));
  }
}

}  // namespace varsfm::testing
