#include "varsfm/dense/match_propagation.h"

#include <cmath>
#include <set>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "varsfm/util/random.h"

namespace varsfm {
namespace {

// A smooth, known displacement field: image 2 at p shows image 1 at p - D(p).
Eigen::Vector2d Disparity(const Eigen::Vector2d& p) {
  return {6.0 + 2.0 * std::sin(p.x() / 40.0), 1.5 + std::cos(p.y() / 50.0)};
}

const cv::Rect kFlat(190, 60, 80, 100);  // constant-colour region of image 1

struct Pair {
  cv::Mat gray1, gray2;
};

Pair MakePair() {
  Rng rng(7);
  std::uniform_int_distribution<int> level(0, 255);
  cv::Mat noise(240, 320, CV_8UC1);
  for (int r = 0; r < noise.rows; ++r)
    for (int c = 0; c < noise.cols; ++c) noise.at<uint8_t>(r, c) = static_cast<uint8_t>(level(rng));
  Pair pair;
  cv::GaussianBlur(noise, pair.gray1, cv::Size(0, 0), 1.2);
  cv::normalize(pair.gray1, pair.gray1, 0, 255, cv::NORM_MINMAX);
  pair.gray1(kFlat).setTo(128);
  cv::Mat map_x(240, 320, CV_32F), map_y(240, 320, CV_32F);
  for (int r = 0; r < 240; ++r)
    for (int c = 0; c < 320; ++c) {
      // Pixel centres: image 2's (c + 0.5, r + 0.5) samples image 1 at that minus D, which in
      // OpenCV's integer-centre coordinates is the same offset from (c, r).
      const Eigen::Vector2d d = Disparity({c + 0.5, r + 0.5});
      map_x.at<float>(r, c) = static_cast<float>(c - d.x());
      map_y.at<float>(r, c) = static_cast<float>(r - d.y());
    }
  cv::remap(pair.gray1, pair.gray2, map_x, map_y, cv::INTER_CUBIC, cv::BORDER_REFLECT);
  return pair;
}

// The true match in image 2 of x1: p with p - D(p) = x1 (fixed point; D is a contraction).
Eigen::Vector2d TrueMatch(const Eigen::Vector2d& x1) {
  Eigen::Vector2d p = x1;
  for (int i = 0; i < 50; ++i) p = x1 + Disparity(p);
  return p;
}

std::vector<SeedMatch> Seeds() {
  std::vector<SeedMatch> seeds;
  for (double y = 30.5; y < 220; y += 60)
    for (double x = 30.5; x < 180; x += 50) seeds.push_back({{x, y}, TrueMatch({x, y})});
  return seeds;
}

TEST(MatchPropagation, RecoversKnownDisparityAndSkipsTexturelessRegion) {
  const Pair pair = MakePair();
  const auto matches = PropagateMatches(pair.gray1, pair.gray2, Seeds());
  // Most of the textured overlap is reached from 12 seeds (the flat box is ~10 % of the image).
  ASSERT_GT(matches.size(), 40000u);
  size_t within_half = 0, in_flat = 0;
  std::vector<double> errors;
  for (const auto& m : matches) {
    const Eigen::Vector2d x2 = m.x2.cast<double>();
    // Checked in image 1's coordinates, where no inversion of D is needed.
    const Eigen::Vector2d err = x2 - Disparity(x2) - m.x1.cast<double>();
    errors.push_back(err.norm());
    if (err.cwiseAbs().maxCoeff() <= 0.5) ++within_half;
    const cv::Point p(static_cast<int>(m.x1.x()), static_cast<int>(m.x1.y()));
    // Interior of the flat region: every window there is constant.
    if (cv::Rect(kFlat.x + 3, kFlat.y + 3, kFlat.width - 6, kFlat.height - 6).contains(p))
      ++in_flat;
  }
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  // Measured: 61354 of 61666 (99.5 %); the rest sit where uniqueness forced a neighbour pixel.
  EXPECT_GE(within_half, matches.size() * 99 / 100);
  EXPECT_LT(errors[errors.size() / 2], 0.15);
  EXPECT_EQ(in_flat, 0u);
}

TEST(MatchPropagation, EveryPixelMatchedAtMostOnce) {
  const Pair pair = MakePair();
  PropagationOptions options;
  options.subpixel = false;  // integer pixels in both images
  const auto matches = PropagateMatches(pair.gray1, pair.gray2, Seeds(), options);
  ASSERT_GT(matches.size(), 1000u);
  std::set<std::pair<int, int>> seen1, seen2;
  for (const auto& m : matches) {
    EXPECT_TRUE(seen1.insert({int(m.x1.x()), int(m.x1.y())}).second);
    EXPECT_TRUE(seen2.insert({int(m.x2.x()), int(m.x2.y())}).second);
    EXPECT_GE(m.zncc, options.min_zncc);
  }
}

TEST(MatchPropagation, EpipolarConstraintBoundsMatches) {
  const Pair pair = MakePair();
  // A horizontal-line F (x2 on the row of x1 shifted by 1.5) contradicts the field's vertical
  // disparity (0.5..2.5 px): growth must stay where |dy - 1.5| <= 1 px.
  Eigen::Matrix3d F;
  F << 0, 0, 0, 0, 0, -1, 0, 1, 1.5;  // x2^T F x1 = y1 + 1.5 - y2: the line y2 = y1 + 1.5
  PropagationOptions options;
  options.max_epipolar_distance = 1.0;
  options.subpixel = false;
  const auto matches = PropagateMatches(pair.gray1, pair.gray2, Seeds(), options, F);
  ASSERT_GT(matches.size(), 100u);
  for (const auto& m : matches) EXPECT_LE(std::abs(m.x2.y() - (m.x1.y() + 1.5)), 1.0 + 1e-6);
}

TEST(MatchPropagation, NoSeedsNoMatches) {
  const Pair pair = MakePair();
  EXPECT_TRUE(PropagateMatches(pair.gray1, pair.gray2, {}).empty());
}

}  // namespace
}  // namespace varsfm
