#include "varsfm/feature/rootsift.h"

#include <cmath>

#include <gtest/gtest.h>

namespace varsfm {
namespace {

TEST(RootSift, NormalisesSquareRootsAndQuantisesAsColmap) {
  cv::Mat sift(3, 128, CV_32F, cv::Scalar(0));
  sift.row(0).setTo(7.0f);  // uniform: sqrt(1/128) * 512 = 45.25 -> 45
  for (int c = 0; c < 16; ++c) sift.at<float>(1, c) = 2.0f;  // sqrt(1/16) * 512 = 128
  // row 2 stays zero: a uniform patch has no gradient, and must not divide by zero.
  const FeatureDescriptors root = RootSiftDescriptors(sift);
  ASSERT_EQ(root.rows(), 3);
  ASSERT_EQ(root.cols(), 128);
  for (int c = 0; c < 128; ++c) {
    EXPECT_EQ(root(0, c), 45);
    EXPECT_EQ(root(1, c), c < 16 ? 128 : 0);
    EXPECT_EQ(root(2, c), 0);
  }
}

TEST(RootSift, LargeComponentsSaturateAt255) {
  cv::Mat sift(1, 128, CV_32F, cv::Scalar(0));
  sift.at<float>(0, 0) = 3.0f;  // sqrt(3/4) * 512 = 443 -> 255
  sift.at<float>(0, 1) = 1.0f;  // sqrt(1/4) * 512 = 256 -> 255
  const FeatureDescriptors root = RootSiftDescriptors(sift);
  EXPECT_EQ(root(0, 0), 255);
  EXPECT_EQ(root(0, 1), 255);
  EXPECT_EQ(root(0, 2), 0);
}

TEST(RootSift, EmptyInputGivesNoRows) {
  const FeatureDescriptors root = RootSiftDescriptors(cv::Mat());
  EXPECT_EQ(root.rows(), 0);
  EXPECT_EQ(root.cols(), 128);
}

}  // namespace
}  // namespace varsfm
