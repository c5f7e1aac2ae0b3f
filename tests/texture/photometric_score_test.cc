// ComparePhotometric (texture/render.h): PSNR, SSIM and coverage over the rendering's mask, and
// the PSNR left once each colour channel's exposure gain is taken out.
#include <cmath>

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "varsfm/texture/render.h"

namespace varsfm {
namespace {

// A smooth colour ramp with room above it for a brighter exposure; the left quarter uncovered.
Rendering RampRendering() {
  Rendering r;
  r.image.create(60, 80, CV_8UC3);
  r.mask = cv::Mat(60, 80, CV_8UC1, cv::Scalar(255));
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 80; ++x)
      r.image.at<cv::Vec3b>(y, x) = cv::Vec3b(40 + x, 30 + y, 60 + x + y);
  r.mask.colRange(0, 20).setTo(0);
  return r;
}

// The photo of another exposure and white balance: each channel the rendering's times a gain.
cv::Mat Exposed(const cv::Mat& image, const cv::Vec3d& gains) {
  cv::Mat photo(image.size(), CV_8UC3);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      for (int c = 0; c < 3; ++c)
        photo.at<cv::Vec3b>(y, x)[c] =
            cv::saturate_cast<uchar>(std::round(gains[c] * image.at<cv::Vec3b>(y, x)[c]));
  return photo;
}

TEST(PhotometricScore, AnotherExposureCostsPsnrButNotExposurePsnr) {
  const Rendering r = RampRendering();
  const PhotometricScore s = ComparePhotometric(r, Exposed(r.image, {0.8, 1.1, 1.25}));
  EXPECT_NEAR(s.coverage, 0.75, 1e-12);
  EXPECT_LT(s.psnr_db, 25.0);  // measured 20.8 dB
  // What is left is the photo's rounding to 8 bits (about 0.3 gray levels RMS): measured 59.1 dB.
  EXPECT_GT(s.psnr_exposure_db, 50.0);
}

TEST(PhotometricScore, NoiseIsNotTakenOutByTheGains) {
  const Rendering r = RampRendering();
  cv::Mat photo = r.image.clone();
  cv::Mat noise(photo.size(), CV_16SC3);
  cv::RNG(7).fill(noise, cv::RNG::NORMAL, 0, 8);
  photo.convertTo(photo, CV_16SC3);
  photo += noise;
  photo.convertTo(photo, CV_8UC3);
  const PhotometricScore s = ComparePhotometric(r, photo);
  // Noise of sigma 8: 30.06 dB, and 30.06 after the gains (they fit what a channel shares).
  EXPECT_NEAR(s.psnr_db, 30.1, 0.5);
  EXPECT_GE(s.psnr_exposure_db, s.psnr_db);
  EXPECT_LT(s.psnr_exposure_db, s.psnr_db + 0.2);
}

TEST(PhotometricScore, IdenticalImagesScoreInfinity) {
  const Rendering r = RampRendering();
  const PhotometricScore s = ComparePhotometric(r, r.image);
  EXPECT_TRUE(std::isinf(s.psnr_db));
  EXPECT_TRUE(std::isinf(s.psnr_exposure_db));
  EXPECT_NEAR(s.ssim, 1.0, 1e-9);
}

}  // namespace
}  // namespace varsfm
