#include "varsfm/feature/sift.h"

#include <cmath>
#include <limits>
#include <vector>

#include <set>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "support/test_data.h"
#include "varsfm/image/image_file.h"

namespace varsfm {
namespace {

// RootSIFT rows are unit vectors before quantisation to 512 x: sum of squares ~ 512^2 (a
// little less where components saturate at 255, and rounding).
void ExpectRootSift(const FeatureDescriptors& descriptors) {
  for (int r = 0; r < descriptors.rows(); ++r) {
    double sum = 0;
    for (int c = 0; c < descriptors.cols(); ++c) sum += std::pow(descriptors(r, c) / 512.0, 2);
    ASSERT_GT(sum, 0.9) << "row " << r;
    ASSERT_LT(sum, 1.02) << "row " << r;
  }
}

// White image with black discs whose centres are known in OpenCV's pixel coordinates.
cv::Mat Discs(std::vector<cv::Point2d>* centers_varsfm) {
  cv::Mat image(300, 400, CV_8UC1, cv::Scalar(255));
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col) {
      const cv::Point center(50 + 100 * col, 50 + 100 * row);
      cv::circle(image, center, 10, cv::Scalar(0), cv::FILLED, cv::LINE_AA);
      // varsfm puts the centre of pixel (i, j) at (i + 0.5, j + 0.5).
      centers_varsfm->emplace_back(center.x + 0.5, center.y + 0.5);
    }
  }
  return image;
}

// Distance from `point` to the nearest keypoint.
double Nearest(const FeatureKeypoints& keypoints, const cv::Point2d& point) {
  double best = std::numeric_limits<double>::max();
  for (const FeatureKeypoint& kp : keypoints) {
    best = std::min(best, std::hypot(kp.x - point.x, kp.y - point.y));
  }
  return best;
}

TEST(Sift, BlobCentresInVarsfmPixelConvention) {
  std::vector<cv::Point2d> centers;
  const cv::Mat image = Discs(&centers);
  const ImageFeatures features = ExtractSift(image, SiftOptions{});
  ASSERT_GE(features.keypoints.size(), centers.size());
  // A symmetric blob is detected at its centre; 0.2 px tells the +0.5 shift apart.
  for (const cv::Point2d& c : centers) EXPECT_LT(Nearest(features.keypoints, c), 0.2) << c;
}

TEST(Sift, DownscaledExtractionMapsBackToOriginalPixels) {
  std::vector<cv::Point2d> centers;
  const cv::Mat image = Discs(&centers);
  SiftOptions options;
  options.max_image_size = 200;  // half size
  const ImageFeatures features = ExtractSift(image, options);
  ASSERT_FALSE(features.keypoints.empty());
  for (const cv::Point2d& c : centers) EXPECT_LT(Nearest(features.keypoints, c), 0.5) << c;
  // The blob radius (10 px) in original pixels: SIFT's sigma of a disc of radius r is about
  // r / sqrt(2), whatever the extraction scale.
  for (const FeatureKeypoint& kp : features.keypoints) {
    if (Nearest({kp}, centers[0]) < 0.5) EXPECT_NEAR(kp.Scale(), 10.0 / std::sqrt(2.0), 2.5);
  }
}

// An image larger than max_image_size is extracted from octave 0 at max_image_size, with no
// upsampled octave: its finest keypoints have sigma 1.6 px at that size (SIFT's base sigma),
// less at most the sub-level interpolation of the scale (half a level, 2^(-1/6)). Upsampling
// would give keypoints down to half that. Random noise has extrema at every scale.
TEST(Sift, LargeImageHasNoUpsampledOctave) {
  cv::Mat noise(600, 800, CV_8UC1);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  SiftOptions options;
  options.max_image_size = 400;  // half size: one pixel there is 2 original pixels
  const ImageFeatures features = ExtractSift(noise, options);
  ASSERT_GT(features.keypoints.size(), 30u);
  const double ratio = 800.0 / options.max_image_size;
  double finest = std::numeric_limits<double>::max();
  for (const FeatureKeypoint& kp : features.keypoints)
    finest = std::min<double>(finest, kp.Scale());
  EXPECT_GE(finest, 1.6 * std::pow(2.0, -1.0 / 6.0) * ratio * 0.99);
  EXPECT_LT(finest, 1.6 * ratio * 1.5);  // the finest octave is there
}

TEST(Sift, FeaturelessImageGivesNoFeatures) {
  const cv::Mat flat(120, 160, CV_8UC1, cv::Scalar(90));
  const ImageFeatures features = ExtractSift(flat, SiftOptions{});
  EXPECT_TRUE(features.keypoints.empty());
  EXPECT_EQ(features.descriptors.rows(), 0);
  EXPECT_EQ(features.descriptors.cols(), 128);
}

TEST(Sift, RealPhotographFeatures) {
  VARSFM_REQUIRE_SHARED_DATA(photo, "bundler/kermit/kermit000.jpg");
  const cv::Mat image = ReadImagePixels(photo, ColorMode::kGray);
  ASSERT_FALSE(image.empty());
  const ImageFeatures features = ExtractSift(image, SiftOptions{});
  EXPECT_GT(features.keypoints.size(), 1000u);
  ASSERT_EQ(features.descriptors.rows(), static_cast<int>(features.keypoints.size()));
  EXPECT_EQ(features.descriptors.cols(), 128);
  for (const FeatureKeypoint& kp : features.keypoints) {
    ASSERT_TRUE(kp.x >= 0 && kp.x <= image.cols && kp.y >= 0 && kp.y <= image.rows);
    ASSERT_GT(kp.Scale(), 0.5f);
  }
  ExpectRootSift(features.descriptors);

  // The cap keeps the strongest 300 locations with all their orientations (as COLMAP): the
  // capped set is the head of the full set (sorted by response) and extraction is
  // deterministic.
  SiftOptions capped;
  capped.max_features = 300;
  const ImageFeatures few = ExtractSift(image, capped);
  std::set<std::pair<float, float>> locations;
  for (const FeatureKeypoint& kp : few.keypoints) locations.emplace(kp.x, kp.y);
  EXPECT_EQ(locations.size(), 300u);
  ASSERT_GE(few.keypoints.size(), 300u);
  for (size_t i = 0; i < few.keypoints.size(); ++i) {
    ASSERT_EQ(few.keypoints[i].x, features.keypoints[i].x) << i;
    ASSERT_EQ(few.keypoints[i].y, features.keypoints[i].y) << i;
  }
  EXPECT_EQ(few.descriptors, features.descriptors.topRows(few.keypoints.size()));
}

// The scale space's size follows the doubled octave of the image SIFT runs on: the image itself
// up to max_image_size, half max_image_size above (sift.cc), so a larger photo may take less.
TEST(SiftMemory, FollowsTheDoubledOctaveOfTheExtractedImage) {
  const SiftOptions options;  // max_image_size 3200
  EXPECT_EQ(SiftMemoryBytes(1024, 683, options), size_t{64} * 2048 * 1366);
  EXPECT_EQ(SiftMemoryBytes(3072, 2048, options), size_t{64} * 6144 * 4096);
  // 4000 x 3000 is extracted at 1600 x 1200.
  EXPECT_EQ(SiftMemoryBytes(4000, 3000, options), size_t{64} * 3200 * 2400);
  EXPECT_LT(SiftMemoryBytes(4000, 3000, options), SiftMemoryBytes(3072, 2048, options));
  EXPECT_LT(SiftMemoryBytes(640, 480, options), SiftMemoryBytes(1024, 683, options));
}

}  // namespace
}  // namespace varsfm
