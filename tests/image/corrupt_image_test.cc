// Image files that crashed the reader (a folder: found by fuzz/obj_fuzzer.cc's smoke run) or made
// it allocate from a size field (found by review): each is now one varsfm::Error naming the
// file, before any pixel buffer is allocated. docs/robustness.md lists them.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/test_data.h"
#include "varsfm/image/image_file.h"
#include "varsfm/image/jpeg_codec.h"
#include "varsfm/image/png_codec.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// CRC-32 of PNG chunks (ISO 3309, as zlib's crc32), bit by bit.
uint32_t Crc32(const uint8_t* data, size_t size) {
  uint32_t crc = 0xFFFFFFFFu;
  for (size_t i = 0; i < size; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void PutBigEndian(std::vector<uint8_t>* bytes, size_t at, uint32_t value) {
  for (int k = 0; k < 4; ++k) (*bytes)[at + k] = static_cast<uint8_t>(value >> (24 - 8 * k));
}

std::string ErrorOf(const std::vector<uint8_t>& bytes) {
  try {
    DecodeImage("bad.png", bytes, ColorMode::kColor);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(CorruptImage, FolderIsAnError) {
  testing::TempDir tmp("corrupt_image");
  // The stream opened on a folder threw std::ios_base::failure from its first read.
  EXPECT_THROW(ReadImagePixels(tmp.path()), Error);
}

TEST(CorruptImage, PngDeclaringMorePixelsThanItsDataCanHold) {
  cv::Mat small(4, 4, CV_8UC3, cv::Scalar(1, 2, 3));
  std::vector<uint8_t> png;
  ASSERT_TRUE(EncodePng(small, &png));
  // IHDR: width at byte 16, height at 20, its CRC (over type and data) at 29. A million by a
  // million pixels made the decoder ask for 3 TB.
  PutBigEndian(&png, 16, 1000000);
  PutBigEndian(&png, 20, 1000000);
  PutBigEndian(&png, 29, Crc32(png.data() + 12, 17));
  EXPECT_NE(ErrorOf(png).find("declares 1000000 x 1000000 pixels, more than its"),
            std::string::npos)
      << ErrorOf(png);
  uint32_t width = 0, height = 0;
  ASSERT_TRUE(PngDimensions(png.data(), png.size(), &width, &height));
  EXPECT_EQ(width, 1000000u);
}

TEST(CorruptImage, JpegBeyondThePixelLimit) {
  cv::Mat small(8, 8, CV_8UC3, cv::Scalar(1, 2, 3));
  std::vector<uint8_t> jpeg;
  ASSERT_TRUE(EncodeJpeg(small, 90, &jpeg));
  // Baseline frame header FF C0: length (2), precision (1), height (2), width (2).
  size_t sof = 2;
  while (sof + 1 < jpeg.size() && !(jpeg[sof] == 0xFF && jpeg[sof + 1] == 0xC0)) ++sof;
  ASSERT_LT(sof + 9, jpeg.size());
  // 65500 x 65500, libjpeg's largest: 12.9 GB as BGR.
  for (size_t at : {sof + 5, sof + 7}) {
    jpeg[at] = 0xFF;
    jpeg[at + 1] = 0xDC;
  }
  int width = 0, height = 0;
  ASSERT_TRUE(JpegDimensions(jpeg.data(), jpeg.size(), &width, &height));
  EXPECT_EQ(width, 65500);
  EXPECT_NE(ErrorOf(jpeg).find("is 65500 x 65500 pixels, more than the"), std::string::npos)
      << ErrorOf(jpeg);
}

}  // namespace
}  // namespace varsfm
