#pragma once
// Rendering a textured mesh from a camera in software (no GPU), to compare with the photo taken
// from it. Visibility by the z-buffer of geometry/rasterizer.h; at every covered pixel the pixel's
// undistorted ray is intersected with its face (perspective-correct, exact under the camera's
// radial distortion: ray = Camera::ImageToNormalized(pixel centre)); the texture coordinates are
// interpolated with those barycentrics and the atlas sampled bilinearly.
#include <opencv2/core.hpp>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"
#include "varsfm/scene/textured_mesh.h"

namespace varsfm {

struct Rendering {
  cv::Mat image;  // BGR 8-bit, black where no face is seen
  cv::Mat mask;   // 8-bit, 255 where a face is seen
};

Rendering RenderTexturedMesh(const TexturedMesh& mesh, const Camera& camera,
                             const Rigid3d& cam_from_world);

// The mesh alone, grey, lit from the camera (Lambert's cosine between the viewing ray and the
// face normal, either side): the geometry as the texture hides it — holes, shards, warps.
// Black where no face is seen.
cv::Mat RenderShadedMesh(const std::vector<Eigen::Vector3d>& vertices,
                         const std::vector<Eigen::Vector3i>& faces, const Camera& camera,
                         const Rigid3d& cam_from_world);

struct PhotometricScore {
  double psnr_db = 0;  // over covered pixels and the three channels; +inf if identical
  // The same after the rendering is scaled by the least-squares gain of each colour channel: the
  // photo's own exposure and white balance, which no single texture reproduces for every photo
  // (a view-synthesis benchmark's colour-corrected PSNR), set apart from the model's error.
  double psnr_exposure_db = 0;
  double ssim = 0;      // over covered pixels (ssim.h: MaskedSsim); 0 when nothing is covered
  double coverage = 0;  // covered pixels / all pixels
  size_t covered_pixels = 0;
};

// PSNR (peak 255) and SSIM between a rendering and the photo over the rendering's mask. Throws
// varsfm::Error when the sizes differ.
PhotometricScore ComparePhotometric(const Rendering& rendering, const cv::Mat& photo);

}  // namespace varsfm
