#include "varsfm/feature/sift.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "varsfm/feature/rootsift.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

namespace {

// The factor ExtractSift resizes an image by before OpenCV's SIFT.
double InputScale(int width, int height, const SiftOptions& options) {
  const int max_side = std::max(width, height);
  if (max_side <= options.max_image_size) return 1.0;
  // OpenCV's SIFT always doubles its input for its first octave (octave -1, Lowe 2004
  // section 3.3): for an image downscaled to max_image_size that interpolates fine detail the
  // downscale has just removed, in an octave of 4x the pixels that costs most of the pyramid.
  // A larger image is downscaled to half max_image_size instead, so that the doubled first
  // octave lies at max_image_size: OpenCV blurs the doubled image from an assumed sigma 1.0
  // (2 x 0.5) to sigma 1.6, and a Gaussian of sigma 1.6 px keeps only
  // exp(-2 pi^2 1.6^2 0.25^2) = 4 % of the frequencies the half-size image cannot hold, so
  // that octave is the max_image_size image's octave 0 (no upsampling), at a quarter of the
  // cost. Images up to max_image_size keep their doubled octave.
  return 0.5 * options.max_image_size / max_side;
}

}  // namespace

ImageFeatures ExtractSift(const cv::Mat& gray, const SiftOptions& options) {
  if (gray.empty() || gray.type() != CV_8UC1) Fail("SIFT expects a non-empty 8-bit grey image");
  if (options.max_features <= 0 || options.max_image_size <= 0) {
    Fail("SIFT options: max features and max image size must be positive");
  }

  cv::Mat input = gray;
  const double scale = InputScale(gray.cols, gray.rows, options);
  if (scale < 1.0) cv::resize(gray, input, cv::Size(), scale, scale, cv::INTER_AREA);
  // Per-axis factors: rounding the resized size makes them differ slightly.
  const float sx = static_cast<float>(gray.cols) / input.cols;
  const float sy = static_cast<float>(gray.rows) / input.rows;

  // nfeatures makes OpenCV keep the strongest keypoints by response before computing
  // descriptors, so the cap costs little descriptor work. OpenCV counts every orientation of a
  // location as a keypoint, COLMAP (like Lowe) caps locations and keeps their orientations, so
  // OpenCV is asked for a margin and the cap on locations is applied below.
  const int opencv_cap = options.max_features + options.max_features / 4;
  cv::Ptr<cv::SIFT> sift =
      cv::SIFT::create(opencv_cap, 3, options.contrast_threshold, options.edge_threshold, 1.6);
  std::vector<cv::KeyPoint> cv_keypoints;
  cv::Mat cv_descriptors;
  sift->detectAndCompute(input, cv::noArray(), cv_keypoints, cv_descriptors);

  // Strongest first, ties broken by position, orientation and size: the order (and which
  // keypoints a cap keeps) then does not depend on OpenCV's internal order, which its own cap
  // (retainBest, an nth_element that also keeps ties at the cut) shuffles.
  std::vector<int> order(cv_keypoints.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const cv::KeyPoint& ka = cv_keypoints[a];
    const cv::KeyPoint& kb = cv_keypoints[b];
    return std::tie(kb.response, ka.pt.y, ka.pt.x, ka.angle, ka.size, a) <
           std::tie(ka.response, kb.pt.y, kb.pt.x, kb.angle, kb.size, b);
  });
  // Keep the strongest `max_features` locations with all their orientations (the extra
  // orientations of a location are separate OpenCV keypoints with the same position, size and
  // response, adjacent in this order).
  {
    size_t kept_end = 0;
    int locations = 0;
    for (size_t i = 0; i < order.size(); ++i) {
      const cv::KeyPoint& kp = cv_keypoints[order[i]];
      const bool same_location = i > 0 && [&] {
        const cv::KeyPoint& prev = cv_keypoints[order[i - 1]];
        return prev.pt == kp.pt && prev.size == kp.size && prev.response == kp.response;
      }();
      if (!same_location && ++locations > options.max_features) break;
      kept_end = i + 1;
    }
    order.resize(kept_end);
  }

  ImageFeatures features;
  features.keypoints.reserve(order.size());
  cv::Mat kept(static_cast<int>(order.size()), cv_descriptors.cols, CV_32F);
  for (size_t i = 0; i < order.size(); ++i) {
    const cv::KeyPoint& kp = cv_keypoints[order[i]];
    // OpenCV puts pixel centres at integers; varsfm at +0.5 (feature/types.h). OpenCV's SIFT
    // also reports every keypoint 0.25 px too far right and down: it doubles the image
    // (first octave -1) with a resize that maps upsampled pixel j to input pixel j/2 - 0.25,
    // then divides coordinates by 2 (measured: a disc centred at (100, 150) comes out at
    // (100.26, 150.26)). Scaling the corrected corner-based coordinate maps the downscaled
    // image exactly onto the original.
    constexpr float kShift = 0.5f - 0.25f;
    const float x = (kp.pt.x + kShift) * sx;
    const float y = (kp.pt.y + kShift) * sy;
    // KeyPoint::size is the diameter (2 sigma) of the region; COLMAP stores sigma.
    const float scale = 0.5f * kp.size * 0.5f * (sx + sy);
    const float orientation = kp.angle * static_cast<float>(CV_PI / 180.0);
    features.keypoints.emplace_back(x, y, scale, orientation);
    cv_descriptors.row(order[i]).copyTo(kept.row(static_cast<int>(i)));
  }
  features.descriptors = RootSiftDescriptors(kept);
  if (features.descriptors.rows() == 0) features.descriptors.resize(0, 128);
  return features;
}

size_t SiftMemoryBytes(int width, int height, const SiftOptions& options) {
  const double scale = InputScale(width, height, options);
  // cv::resize rounds the size; the doubled octave has twice the input's sides.
  const double doubled_pixels = 4.0 * std::round(scale * width) * std::round(scale * height);
  return static_cast<size_t>(64.0 * doubled_pixels);
}

void SiftOptions::Check() const {
  CheckAtLeast("--max-features", max_features, 1);
  CheckAtLeast("--max-image-size", max_image_size, 16);
  CheckPositive("--contrast-threshold", contrast_threshold);
  CheckPositive("edge_threshold", edge_threshold);
}

}  // namespace varsfm
