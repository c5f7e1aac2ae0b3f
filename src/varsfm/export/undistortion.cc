#include "varsfm/export/undistortion.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// Samples per image side when tracing the photo's border through the undistortion: dense enough
// that the rectangle's edges are within a small fraction of a pixel for smooth radial models.
constexpr int kBorderSamples = 256;

// Pinhole pixel (same focal lengths, principal point unchanged, no skew) of a distorted pixel.
Eigen::Vector2d IdealPixel(const Camera& camera, const Eigen::Vector2d& pixel) {
  const Eigen::Vector2d n = camera.ImageToNormalized(pixel);
  return {camera.focal() * n.x() + camera.params[Camera::kU0],
          camera.fy() * n.y() + camera.params[Camera::kV0]};
}

}  // namespace

Camera UndistortedPinholeCamera(const Camera& camera, PrincipalPointPlacement placement) {
  // The rectangle inside the traced border: the innermost x of the left and right edges and the
  // innermost y of the top and bottom edges.
  double left = -std::numeric_limits<double>::infinity();
  double right = std::numeric_limits<double>::infinity();
  double top = -std::numeric_limits<double>::infinity();
  double bottom = std::numeric_limits<double>::infinity();
  const double w = camera.width;
  const double h = camera.height;
  for (int i = 0; i <= kBorderSamples; ++i) {
    const double s = static_cast<double>(i) / kBorderSamples;
    left = std::max(left, IdealPixel(camera, {0.0, s * h}).x());
    right = std::min(right, IdealPixel(camera, {w, s * h}).x());
    top = std::max(top, IdealPixel(camera, {s * w, 0.0}).y());
    bottom = std::min(bottom, IdealPixel(camera, {s * w, h}).y());
  }
  const double u0 = camera.params[Camera::kU0];
  const double v0 = camera.params[Camera::kV0];
  double width = std::floor(right - left);
  double height = std::floor(bottom - top);
  double cx = u0 - left, cy = v0 - top;
  if (placement == PrincipalPointPlacement::kCentred) {
    // The principal point keeps its place in the ideal image; the rectangle's sides move to it:
    // the nearer of each pair of edges bounds both (the far side gives up what the near one
    // lacks). The edges may then fall between pixels of the ideal image: the image is resampled.
    width = std::floor(2.0 * std::min(u0 - left, right - u0));
    height = std::floor(2.0 * std::min(v0 - top, bottom - v0));
    cx = 0.5 * width;
    cy = 0.5 * height;
  }
  if (!(width >= 2 && height >= 2)) {
    Fail("camera {}: its distortion (k1 {:.3g}, k2 {:.3g}){} leaves no valid undistorted image",
         camera.camera_id, camera.params[Camera::kK1], camera.params[Camera::kK2],
         placement == PrincipalPointPlacement::kCentred
             ? fmt::format(" and principal point ({:.1f}, {:.1f})", u0, v0)
             : "");
  }
  Camera pinhole;
  pinhole.camera_id = camera.camera_id;
  pinhole.width = static_cast<int>(width);
  pinhole.height = static_cast<int>(height);
  pinhole.params = {camera.focal(), camera.params[Camera::kAspect], 0.0, cx, cy, 0.0, 0.0};
  return pinhole;
}

Eigen::Vector2d UndistortPixel(const Camera& camera, const Camera& pinhole,
                               const Eigen::Vector2d& pixel) {
  return pinhole.NormalizedToImage(camera.ImageToNormalized(pixel));
}

cv::Mat UndistortImage(const cv::Mat& image, const Camera& camera, const Camera& pinhole) {
  if (image.cols != camera.width || image.rows != camera.height) {
    Fail("image of {}x{} pixels does not match its camera's {}x{}", image.cols, image.rows,
         camera.width, camera.height);
  }
  cv::Mat map_x(pinhole.height, pinhole.width, CV_32F);
  cv::Mat map_y(pinhole.height, pinhole.width, CV_32F);
  for (int y = 0; y < pinhole.height; ++y) {
    float* mx = map_x.ptr<float>(y);
    float* my = map_y.ptr<float>(y);
    for (int x = 0; x < pinhole.width; ++x) {
      const Eigen::Vector2d n = pinhole.ImageToNormalized({x + 0.5, y + 0.5});
      const Eigen::Vector2d p = camera.NormalizedToImage(n);
      // OpenCV samples with pixel centres at integers; varsfm's are at half-integers.
      mx[x] = static_cast<float>(p.x() - 0.5);
      my[x] = static_cast<float>(p.y() - 0.5);
    }
  }
  cv::Mat undistorted;
  // Bicubic: every output pixel falls between the photo's (a sub-pixel crop at the least), and
  // at half a pixel bilinear interpolation blurs the photos a splatting loss is fitted to: it
  // loses 1.3 dB more than bicubic against the true half-pixel shift (bench/resampling_loss.py,
  // docs/measurements.md). 8-bit results are saturated, so bicubic overshoot is clipped.
  cv::remap(image, undistorted, map_x, map_y, cv::INTER_CUBIC, cv::BORDER_REPLICATE);
  return undistorted;
}

}  // namespace varsfm
