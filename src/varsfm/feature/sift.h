#pragma once
// SIFT keypoints and RootSIFT descriptors of one image, in varsfm's pixel convention.
#include <opencv2/core.hpp>

#include "varsfm/feature/types.h"

namespace varsfm {

struct SiftOptions {
  // Keep at most this many features, the strongest by detector response.
  int max_features = 8192;
  // Images whose larger side exceeds this are downscaled for extraction (speed and memory);
  // keypoints are scaled back to the original pixels.
  int max_image_size = 3200;
  // OpenCV's contrast threshold (Lowe's 0.03 in units of a [0,1] image, scaled by OpenCV by
  // the number of layers); lower gives more, weaker features.
  double contrast_threshold = 0.02;
  double edge_threshold = 10.0;
};

struct ImageFeatures {
  FeatureKeypoints keypoints;
  FeatureDescriptors descriptors;  // one RootSIFT row (128 uint8) per keypoint
};

// Extracts features from a grey 8-bit image. Deterministic.
ImageFeatures ExtractSift(const cv::Mat& gray, const SiftOptions& options);

}  // namespace varsfm
