#pragma once
// SIFT keypoints and RootSIFT descriptors of one image, in varsfm's pixel convention.
#include <opencv2/core.hpp>

#include "varsfm/feature/types.h"

namespace varsfm {

// The version of ExtractSift's output: bump whenever the extractor's output changes for the same
// options, so that a workspace's features from an older extractor are extracted again (the
// workspace records it with the options, pipeline/extract.cc). 2: an image larger than
// max_image_size is extracted from octave 0 at max_image_size (sift.cc); 1, or no version
// recorded: from an upsampled octave -1 at max_image_size.
inline constexpr int kSiftExtractorVersion = 2;

struct SiftOptions {
  // Keep at most this many feature locations, the strongest by detector response, with all
  // their orientations (as COLMAP's max_num_features).
  int max_features = 8192;
  // The finest scale of a large image: an image whose larger side exceeds this is extracted at
  // this size, from octave 0 (no upsampled octave; sift.cc says how), for speed and memory.
  // Smaller images are extracted at their size from an upsampled octave -1 (Lowe 2004).
  // Keypoints are scaled back to the original pixels.
  int max_image_size = 3200;
  // OpenCV's contrast threshold (in units of a [0,1] image, divided by OpenCV by the number of
  // layers, 3); lower gives more, weaker features. 0.02 is COLMAP's peak threshold (0.02 / 3);
  // 0.013 gives more verified inliers on fountain-P11, where every image then reaches the
  // 8192-location cap (bench/features_vs_colmap.sh, docs/measurements.md).
  double contrast_threshold = 0.013;
  double edge_threshold = 10.0;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct ImageFeatures {
  FeatureKeypoints keypoints;
  FeatureDescriptors descriptors;  // one RootSIFT row (128 uint8) per keypoint
};

// Extracts features from a grey 8-bit image. Deterministic.
ImageFeatures ExtractSift(const cv::Mat& gray, const SiftOptions& options);

// About the memory ExtractSift's scale space takes for an image of this size (bytes): OpenCV
// keeps every octave's 6 Gaussian and 5 difference-of-Gaussian float images, the octaves together
// 4/3 of the first, which is the doubled input (octave -1): with the input's float copies, some
// 64 bytes per pixel of that octave. A 3072 x 2048 photo: 1.6 GB; a 4000 x 3000 one, extracted
// at 1600 x 1200 (sift.cc): 0.5 GB.
size_t SiftMemoryBytes(int width, int height, const SiftOptions& options);

}  // namespace varsfm
