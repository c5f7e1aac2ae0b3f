#include "varsfm/image/raw_codec.h"

#include <cmath>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "image/decode_error.h"
#include "support/dng_writer.h"
#include "support/test_data.h"
#include "varsfm/image/image_io.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// Bright on the left, dark on the right, with texture: the halves show where the sensor's left
// edge went after developing.
cv::Mat HalfBright(int width, int height) {
  cv::Mat image(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const uint8_t base = x < width / 2 ? 200 : 40;
      image.at<cv::Vec3b>(y, x) = cv::Vec3b::all(static_cast<uint8_t>(base + (x * 7 + y * 3) % 20));
    }
  return image;
}

double MeanOf(const cv::Mat& image, const cv::Rect& part) { return cv::mean(image(part))[0]; }

TEST(RawCodec, DevelopsADngInColourAndGrey) {
  const std::vector<uint8_t> dng = testing::EncodeDng(HalfBright(96, 64));
  EXPECT_TRUE(IsRawPhotoName("IMG_0001.DNG"));
  EXPECT_FALSE(IsRawPhotoName("IMG_0001.tif"));
  const cv::Mat colour = DecodeImage("IMG_0001.DNG", dng, ColorMode::kColor);
  ASSERT_EQ(colour.type(), CV_8UC3);
  ASSERT_EQ(colour.size(), cv::Size(96, 64));
  const cv::Mat grey = DecodeImage("IMG_0001.DNG", dng, ColorMode::kGray);
  ASSERT_EQ(grey.type(), CV_8UC1);
  ASSERT_EQ(grey.size(), cv::Size(96, 64));
  EXPECT_GT(MeanOf(grey, {8, 8, 32, 48}), MeanOf(grey, {56, 8, 32, 48}) + 60);
}

// A camera held upright writes its sensor's pixels and an orientation; developed upright.
TEST(RawCodec, AppliesTheOrientation) {
  const std::vector<uint8_t> dng = testing::EncodeDng(HalfBright(96, 64), 6);
  const cv::Mat upright = DecodeImage("turned.dng", dng, ColorMode::kGray);
  ASSERT_EQ(upright.size(), cv::Size(64, 96));
  // Turned a quarter clockwise, the sensor's left half is the top.
  EXPECT_GT(MeanOf(upright, {8, 8, 48, 32}), MeanOf(upright, {8, 56, 48, 32}) + 60);
}

TEST(RawCodec, ACorruptRawFileIsAOneLineError) {
  std::vector<uint8_t> dng = testing::EncodeDng(HalfBright(64, 48));
  dng.resize(60);
  EXPECT_THROW(DecodeImage("cut.dng", dng, ColorMode::kColor), Error);
  const std::vector<uint8_t> text = {'n', 'o', 't', ' ', 'r', 'a', 'w'};
  const std::string error = testing::DecodeErrorOf("text.CR2", text);
  EXPECT_NE(error.find("text.CR2 is not a decodable image"), std::string::npos) << error;
}

TEST(ReadPhoto, ReadsARawPhotosFocalLength) {
  testing::TempDir dir("raw_focal");
  const std::vector<uint8_t> dng = testing::EncodeDng(HalfBright(96, 64), 1, 28);
  std::ofstream(dir.path() / "a.dng", std::ios::binary)
      .write(reinterpret_cast<const char*>(dng.data()), static_cast<std::streamsize>(dng.size()));
  const Photo photo = ReadPhoto(dir.path() / "a.dng", ColorMode::kGray);
  ASSERT_TRUE(photo.exif_focal_px.has_value());
  EXPECT_NEAR(*photo.exif_focal_px, 28.0 * std::hypot(96.0, 64.0) / std::hypot(36.0, 24.0), 1e-9);
  EXPECT_EQ(RawFocalLength35mm(dng.data(), dng.size()), 28.0);
  const std::vector<uint8_t> bare = testing::EncodeDng(HalfBright(96, 64));
  EXPECT_FALSE(RawFocalLength35mm(bare.data(), bare.size()).has_value());
}

}  // namespace
}  // namespace varsfm
