#pragma once
// A registered photo undistorted into a pinhole image (possibly downscaled) for dense matching.
#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "varsfm/camera/camera.h"

namespace varsfm {

// The undistorted, possibly downscaled image of a registered view and its pinhole camera.
struct UndistortedView {
  cv::Mat color;  // BGR 8-bit
  cv::Mat gray;
  Eigen::Matrix3d K;
  double scale = 1.0;  // matching image size / original size
};

// Undistorts `image` (the original photo of `camera`) into a pinhole image with the same K
// (scaled by `scale`): every output pixel samples the photo where the full camera model
// (distortion included) projects its ray.
UndistortedView UndistortImage(const cv::Mat& image, const Camera& camera, double scale);

// UndistortImage downscaled so that its longer side is at most `max_image_size` pixels (never
// upscaled): the images the dense methods match.
UndistortedView UndistortAtMostSize(const cv::Mat& image, const Camera& camera, int max_image_size);

}  // namespace varsfm
