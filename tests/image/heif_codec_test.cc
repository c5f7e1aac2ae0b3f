#include "varsfm/image/heif_codec.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "image/decode_error.h"
#include "support/heif_writer.h"
#include "support/test_data.h"
#include "varsfm/image/jpeg_codec.h"

namespace varsfm {
namespace {

// Smooth colour ramps and a disc: little for the lossy encoder to lose, and no symmetry.
cv::Mat Pattern(int width, int height) {
  cv::Mat image(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.at<cv::Vec3b>(y, x) = {static_cast<uint8_t>(255 * x / width),
                                   static_cast<uint8_t>(255 * y / height), 120};
  cv::circle(image, {width / 3, height / 3}, height / 5, cv::Scalar(30, 200, 240), cv::FILLED);
  return image;
}

double MeanAbsoluteDifference(const cv::Mat& a, const cv::Mat& b) {
  return cv::norm(a, b, cv::NORM_L1) / static_cast<double>(a.total() * a.channels());
}

TEST(HeifCodec, DecodesAHeicPhotoInColourAndGrey) {
  const cv::Mat photo = Pattern(160, 96);
  const std::vector<uint8_t> heic = testing::EncodeHeic(photo);
  ASSERT_FALSE(heic.empty());
  EXPECT_TRUE(LooksLikeHeif(heic.data(), heic.size()));
  const cv::Mat colour = DecodeImage("IMG_0001.HEIC", heic, ColorMode::kColor);
  ASSERT_EQ(colour.type(), CV_8UC3);
  ASSERT_EQ(colour.size(), photo.size());
  EXPECT_LT(MeanAbsoluteDifference(colour, photo), 3.0);
  const cv::Mat grey = DecodeImage("IMG_0001.HEIC", heic, ColorMode::kGray);
  ASSERT_EQ(grey.type(), CV_8UC1);
  cv::Mat expected;
  cv::cvtColor(photo, expected, cv::COLOR_BGR2GRAY);
  EXPECT_LT(MeanAbsoluteDifference(grey, expected), 3.0);
}

// A phone held sideways stores its pixels as the sensor read them and a rotation (or mirror)
// property; every orientation comes out upright.
TEST(HeifCodec, AppliesTheFilesRotationAndMirror) {
  const cv::Mat stored = Pattern(120, 80);
  const auto turned = [&](int orientation) {
    cv::Mat out;
    switch (orientation) {
      case 3:
        cv::rotate(stored, out, cv::ROTATE_180);
        break;
      case 6:
        cv::rotate(stored, out, cv::ROTATE_90_CLOCKWISE);
        break;
      case 8:
        cv::rotate(stored, out, cv::ROTATE_90_COUNTERCLOCKWISE);
        break;
      case 2:
        cv::flip(stored, out, 1);
        break;
      default:
        out = stored;
    }
    return out;
  };
  for (const int orientation : {1, 2, 3, 6, 8}) {
    const std::vector<uint8_t> heic = testing::EncodeHeic(stored, 90, orientation);
    const cv::Mat upright = DecodeImage("turned.heic", heic, ColorMode::kColor);
    const cv::Mat expected = turned(orientation);
    ASSERT_EQ(upright.size(), expected.size()) << orientation;
    EXPECT_LT(MeanAbsoluteDifference(upright, expected), 3.0) << orientation;
  }
}

TEST(HeifCodec, ACorruptHeicIsAOneLineError) {
  std::vector<uint8_t> heic = testing::EncodeHeic(Pattern(64, 48));
  ASSERT_GT(heic.size(), 400u);
  heic.resize(heic.size() / 2);
  const std::string error = testing::DecodeErrorOf("cut.heic", heic);
  EXPECT_NE(error.find("cut.heic is not a decodable image"), std::string::npos) << error;
  EXPECT_TRUE(HeifExif(heic.data(), heic.size()).empty());
  std::vector<uint8_t> jpeg;
  ASSERT_TRUE(EncodeJpeg(Pattern(64, 48), 90, &jpeg));
  EXPECT_FALSE(LooksLikeHeif(jpeg.data(), jpeg.size()));
}

}  // namespace
}  // namespace varsfm
