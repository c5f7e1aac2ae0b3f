#include "varsfm/image/scratch_image.h"

#include <gtest/gtest.h>

#include "support/test_data.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

TEST(CopyToScratch, SamePixelsSharedByCopiesAndNoFileLeft) {
  testing::TempDir tmp("scratch_image");
  cv::Mat image(37, 53, CV_8UC3);
  cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(255));
  cv::Mat gray(37, 53, CV_32F);
  cv::randu(gray, 0.0f, 1.0f);
  {
    const cv::Mat colour = CopyToScratch(image, tmp.path());
    const cv::Mat grey = CopyToScratch(gray, tmp.path());
    ASSERT_EQ(colour.size(), image.size());
    ASSERT_EQ(colour.type(), image.type());
    EXPECT_EQ(cv::norm(colour, image, cv::NORM_INF), 0);
    EXPECT_EQ(cv::norm(grey, gray, cv::NORM_INF), 0);
    EXPECT_NE(colour.data, image.data);
    cv::Mat shared = colour;  // a header: the same scratch pixels
    EXPECT_EQ(shared.data, colour.data);
    cv::Mat clone = colour.clone();  // on the heap
    EXPECT_EQ(cv::norm(clone, image, cv::NORM_INF), 0);
    EXPECT_EQ(fs::directory_iterator(tmp.path()), fs::directory_iterator());
  }
  EXPECT_EQ(fs::directory_iterator(tmp.path()), fs::directory_iterator());
}

}  // namespace
}  // namespace varsfm
