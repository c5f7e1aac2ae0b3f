#include "varsfm/texture/ssim.h"

#include <gtest/gtest.h>

#include <random>

#include <opencv2/core.hpp>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

cv::Mat Noise(unsigned seed) {
  cv::Mat image(64, 80, CV_8UC3);
  std::mt19937 rng(seed);
  for (size_t i = 0; i < image.total() * image.elemSize(); ++i) image.data[i] = rng() & 0xff;
  return image;
}

cv::Mat FullMask() { return cv::Mat(64, 80, CV_8UC1, cv::Scalar(255)); }

TEST(Ssim, IdenticalImagesScoreOne) {
  const cv::Mat a = Noise(1);
  EXPECT_NEAR(MaskedSsim(a, a, FullMask()), 1.0, 1e-12);
}

// Two flat images: variances and covariance vanish, so SSIM is the luminance term alone,
// (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1).
TEST(Ssim, FlatImagesGiveTheLuminanceTerm) {
  const cv::Mat a(64, 80, CV_8UC3, cv::Scalar(100, 100, 100));
  const cv::Mat b(64, 80, CV_8UC3, cv::Scalar(120, 120, 120));
  const double c1 = (0.01 * 255) * (0.01 * 255);
  EXPECT_NEAR(MaskedSsim(a, b, FullMask()), (2 * 100 * 120 + c1) / (100 * 100 + 120 * 120 + c1),
              1e-9);
}

TEST(Ssim, UnrelatedNoiseScoresNearZero) {
  EXPECT_LT(std::abs(MaskedSsim(Noise(1), Noise(2), FullMask())), 0.05);
}

// Differences outside the mask, and within a window's reach of its edge, do not count.
TEST(Ssim, OnlyTheMaskIsScored) {
  const cv::Mat a = Noise(1);
  cv::Mat b = a.clone();
  b.colRange(40, 80).setTo(cv::Scalar(0, 0, 0));
  cv::Mat mask = cv::Mat::zeros(64, 80, CV_8UC1);
  mask.colRange(0, 40).setTo(255);
  EXPECT_NEAR(MaskedSsim(a, b, mask), 1.0, 1e-12);
  EXPECT_EQ(MaskedSsim(a, b, cv::Mat::zeros(64, 80, CV_8UC1)), 0.0);
}

TEST(Ssim, MismatchedSizesAreRefused) {
  EXPECT_THROW(MaskedSsim(Noise(1), cv::Mat(10, 10, CV_8UC3), FullMask()), Error);
}

}  // namespace
}  // namespace varsfm
