#include "varsfm/dense/zncc.h"

#include <cmath>

#include <gtest/gtest.h>

#include "varsfm/util/error.h"
#include "varsfm/util/random.h"

namespace varsfm {
namespace {

cv::Mat RandomImage(int width, int height, uint64_t seed) {
  Rng rng(seed);
  std::uniform_int_distribution<int> level(0, 255);
  cv::Mat image(height, width, CV_8UC1);
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) image.at<uint8_t>(r, c) = static_cast<uint8_t>(level(rng));
  return image;
}

// The textbook definition, in double precision.
double DirectZncc(const cv::Mat& a, int xa, int ya, const cv::Mat& b, int xb, int yb, int r) {
  double ma = 0, mb = 0;
  const double n = (2.0 * r + 1) * (2.0 * r + 1);
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      ma += a.at<uint8_t>(ya + dy, xa + dx), mb += b.at<uint8_t>(yb + dy, xb + dx);
  ma /= n, mb /= n;
  double cov = 0, va = 0, vb = 0;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      const double p = a.at<uint8_t>(ya + dy, xa + dx) - ma,
                   q = b.at<uint8_t>(yb + dy, xb + dx) - mb;
      cov += p * q, va += p * p, vb += q * q;
    }
  return cov / std::sqrt(va * vb);
}

TEST(Zncc, MatchesTheDefinitionForEveryRadius) {
  const cv::Mat a = RandomImage(61, 47, 1), b = RandomImage(61, 47, 2);
  for (int r : {1, 3, 4, 7}) {
    const ZnccImage ia(a, r, 1.0), ib(b, r, 1.0);
    for (int y = r; y < a.rows - r; y += 5)
      for (int x = r; x < a.cols - r; x += 3) {
        const ZnccWindow w(ia, x, y);
        // Against a shifted window of the other image and against itself (1).
        const int xb = std::min(x + 2, b.cols - r - 1), yb = std::max(y - 1, r);
        EXPECT_NEAR(w.Score(ib, xb, yb), DirectZncc(a, x, y, b, xb, yb, r), 1e-5) << r;
        EXPECT_NEAR(w.Score(ia, x, y), 1.0, 1e-5);
      }
  }
}

TEST(Zncc, InvariantToGainAndOffset) {
  const cv::Mat a = RandomImage(40, 30, 3);
  cv::Mat b;
  a.convertTo(b, CV_8UC1, 0.5, 40);  // b = 0.5 a + 40: ZNCC 1 up to rounding
  const ZnccImage ia(a, 3, 1.0), ib(b, 3, 1.0);
  EXPECT_GT(ZnccWindow(ia, 20, 15).Score(ib, 20, 15), 0.99f);
}

TEST(Zncc, FlatWindowsNeverMatch) {
  cv::Mat a = RandomImage(40, 30, 4);
  a(cv::Rect(10, 10, 12, 12)).setTo(90);
  const ZnccImage ia(a, 3, 1.0);
  EXPECT_TRUE(ia.Flat(ia.Index(16, 16)));
  EXPECT_TRUE(ZnccWindow(ia, 16, 16).Flat());
  EXPECT_EQ(ZnccWindow(ia, 16, 16).Score(ia, 16, 16), -1.f);
  EXPECT_EQ(ZnccWindow(ia, 30, 20).Score(ia, 16, 16), -1.f);
  EXPECT_FALSE(ia.Flat(ia.Index(30, 20)));
  EXPECT_TRUE(ia.Flat(ia.Index(1, 1)));  // window off the image
}

TEST(Zncc, RejectsBadInput) {
  EXPECT_THROW(ZnccImage(cv::Mat(), 3, 1.0), Error);
  EXPECT_THROW(ZnccImage(cv::Mat(10, 10, CV_32F), 3, 1.0), Error);
  EXPECT_THROW(ZnccImage(cv::Mat(10, 10, CV_8UC1), 0, 1.0), Error);
  EXPECT_THROW(ZnccImage(cv::Mat(10, 10, CV_8UC1), ZnccImage::kMaxRadius + 1, 1.0), Error);
}

}  // namespace
}  // namespace varsfm
