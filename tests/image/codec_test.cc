// The direct JPEG/PNG codecs and the EXIF orientation (image_file.h, jpeg_codec.h,
// png_codec.h, orientation.h). Pixel identity with OpenCV's imgcodecs was checked when they
// replaced it; these tests pin the behaviour that identity relies on.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "support/test_data.h"
#include "varsfm/image/exif.h"
#include "varsfm/image/image_file.h"
#include "varsfm/image/jpeg_codec.h"
#include "varsfm/image/orientation.h"
#include "varsfm/image/png_codec.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

cv::Mat RandomImage(int width, int height, int type) {
  cv::Mat image(height, width, type);
  cv::RNG(5).fill(image, cv::RNG::UNIFORM, 0, type == CV_16UC3 ? 65536 : 256);
  return image;
}

bool Identical(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

// "Exif\0\0" and a little-endian TIFF header whose IFD0 holds one Orientation entry.
std::vector<uint8_t> ExifWithOrientation(uint16_t orientation) {
  return {'E', 'x',  'i',  'f', 0,
          0,   'I',  'I',  42,  0,
          8,   0,    0,    0,   1,
          0,   0x12, 0x01, 3,   0,
          1,   0,    0,    0,   static_cast<uint8_t>(orientation),
          0,   0,    0,    0,   0,
          0,   0};
}

TEST(PngCodec, RoundTripsGreyColourAndAlpha) {
  for (const int type : {CV_8UC1, CV_8UC3}) {
    const cv::Mat image = RandomImage(37, 21, type);
    std::vector<uint8_t> png;
    ASSERT_TRUE(EncodePng(image, &png));
    EXPECT_TRUE(LooksLikePng(png.data(), png.size()));
    const ColorMode mode = type == CV_8UC1 ? ColorMode::kGray : ColorMode::kColor;
    EXPECT_TRUE(Identical(DecodePng(png.data(), png.size(), mode), image));
  }
  // Alpha is dropped on reading, as cv::imread(IMREAD_COLOR) does.
  const cv::Mat bgra = RandomImage(9, 7, CV_8UC4);
  std::vector<uint8_t> png;
  ASSERT_TRUE(EncodePng(bgra, &png));
  cv::Mat bgr;
  cv::extractChannel(bgra, bgr, 0);
  const cv::Mat decoded = DecodePng(png.data(), png.size(), ColorMode::kColor);
  ASSERT_EQ(decoded.type(), CV_8UC3);
  cv::Mat blue;
  cv::extractChannel(decoded, blue, 0);
  EXPECT_TRUE(Identical(blue, bgr));
}

TEST(PngCodec, SixteenBitSamplesKeepTheirHighByte) {
  const cv::Mat image = RandomImage(16, 8, CV_16UC3);
  std::vector<uint8_t> png;
  ASSERT_TRUE(EncodePng(image, &png));
  cv::Mat high(image.size(), CV_8UC3);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x)
      for (int c = 0; c < 3; ++c)
        high.at<cv::Vec3b>(y, x)[c] = static_cast<uint8_t>(image.at<cv::Vec3w>(y, x)[c] >> 8);
  EXPECT_TRUE(Identical(DecodePng(png.data(), png.size(), ColorMode::kColor), high));
}

TEST(PngCodec, GarbageIsNotDecoded) {
  std::vector<uint8_t> png;
  ASSERT_TRUE(EncodePng(RandomImage(20, 20, CV_8UC3), &png));
  png.resize(png.size() / 2);
  EXPECT_TRUE(DecodePng(png.data(), png.size(), ColorMode::kColor).empty());
  const std::string text = "not a png";
  EXPECT_TRUE(
      DecodePng(reinterpret_cast<const uint8_t*>(text.data()), text.size(), ColorMode::kColor)
          .empty());
}

TEST(JpegCodec, EncodesAndDecodesGreyAndColour) {
  for (const int type : {CV_8UC1, CV_8UC3}) {
    cv::Mat image(48, 64, type, cv::Scalar(40, 120, 200));
    std::vector<uint8_t> jpeg;
    ASSERT_TRUE(EncodeJpeg(image, 95, &jpeg));
    const ColorMode mode = type == CV_8UC1 ? ColorMode::kGray : ColorMode::kColor;
    const std::optional<cv::Mat> decoded = DecodeJpeg(jpeg.data(), jpeg.size(), mode);
    ASSERT_TRUE(decoded.has_value());
    ASSERT_EQ(decoded->type(), type);
    EXPECT_LE(cv::norm(*decoded, image, cv::NORM_INF), 2.0);  // flat colour: nearly lossless
  }
  EXPECT_FALSE(EncodeJpeg(cv::Mat(4, 4, CV_32FC1), 95, nullptr));
}

TEST(ExifOrientation, ReadsTheTagAndDefaultsToUpright) {
  for (uint16_t o = 1; o <= 8; ++o) {
    const std::vector<uint8_t> exif = ExifWithOrientation(o);
    EXPECT_EQ(ExifOrientation(exif.data(), exif.size()), o);
  }
  const std::vector<uint8_t> invalid = ExifWithOrientation(9);
  EXPECT_EQ(ExifOrientation(invalid.data(), invalid.size()), 1);
  EXPECT_EQ(ExifOrientation(nullptr, 0), 1);
}

TEST(ExifOrientation, TurnsPixelsAsTheTagSays) {
  const cv::Mat stored = (cv::Mat_<uint8_t>(2, 3) << 1, 2, 3, 4, 5, 6);
  auto oriented = [&](int orientation) {
    cv::Mat image = stored.clone();
    ApplyExifOrientation(orientation, &image);
    return image;
  };
  cv::Mat expected;
  EXPECT_TRUE(Identical(oriented(1), stored));
  cv::flip(stored, expected, 1);
  EXPECT_TRUE(Identical(oriented(2), expected));
  cv::rotate(stored, expected, cv::ROTATE_180);
  EXPECT_TRUE(Identical(oriented(3), expected));
  cv::flip(stored, expected, 0);
  EXPECT_TRUE(Identical(oriented(4), expected));
  EXPECT_TRUE(Identical(oriented(5), stored.t()));
  cv::rotate(stored, expected, cv::ROTATE_90_CLOCKWISE);
  EXPECT_TRUE(Identical(oriented(6), expected));
  cv::rotate(stored.t(), expected, cv::ROTATE_180);
  EXPECT_TRUE(Identical(oriented(7), expected));
  cv::rotate(stored, expected, cv::ROTATE_90_COUNTERCLOCKWISE);
  EXPECT_TRUE(Identical(oriented(8), expected));
}

TEST(WriteImage, PngAndJpegDirectlyOtherFormatsThroughThePlugin) {
  testing::TempDir dir("write_image");
  const cv::Mat image = RandomImage(30, 20, CV_8UC3);
  for (const char* name : {"a.png", "a.PNG", "a.bmp", "a.tif"}) {
    SCOPED_TRACE(name);
    WriteImage(dir.path() / name, image);
    EXPECT_TRUE(Identical(ReadImagePixels(dir.path() / name), image));
  }
  WriteImage(dir.path() / "a.jpg", image, ImageWriteOptions{90});
  EXPECT_EQ(ReadImagePixels(dir.path() / "a.jpg").size(), image.size());
  EXPECT_THROW(WriteImage(dir.path() / "a.unknown", image), Error);
  EXPECT_THROW(WriteImage(dir.path() / "absent" / "a.png", image), Error);
  // The plug-in's formats go through a temporary too: only the images are left, no temporary
  // of the failed write.
  size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    EXPECT_NE(entry.path().filename().string().front(), '.') << entry.path();
    ++files;
  }
  EXPECT_EQ(files, 5u);
}

}  // namespace
}  // namespace varsfm
