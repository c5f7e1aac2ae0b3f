#include "varsfm/image/exif.h"

#include <libexif/exif-data.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "support/heif_writer.h"
#include "support/test_data.h"
#include "varsfm/image/image_io.h"
#include "varsfm/image/jpeg_codec.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

// Builds an EXIF block with libexif and inserts it as an APP1 segment into a JPEG, as a camera
// would write it.
class ExifWriter {
 public:
  ExifWriter() : exif_(exif_data_new()) {
    exif_data_set_byte_order(exif_, EXIF_BYTE_ORDER_INTEL);
    exif_data_set_data_type(exif_, EXIF_DATA_TYPE_COMPRESSED);
  }
  ~ExifWriter() { exif_data_unref(exif_); }

  void Short(ExifIfd ifd, ExifTag tag, uint16_t value) {
    exif_set_short(Add(ifd, tag, EXIF_FORMAT_SHORT)->data, EXIF_BYTE_ORDER_INTEL, value);
  }
  void Long(ExifIfd ifd, ExifTag tag, uint32_t value) {
    exif_set_long(Add(ifd, tag, EXIF_FORMAT_LONG)->data, EXIF_BYTE_ORDER_INTEL, value);
  }
  void Rational(ExifIfd ifd, ExifTag tag, uint32_t numerator, uint32_t denominator) {
    exif_set_rational(Add(ifd, tag, EXIF_FORMAT_RATIONAL)->data, EXIF_BYTE_ORDER_INTEL,
                      {numerator, denominator});
  }

  // The EXIF block as libexif saves it: "Exif\0\0", then the TIFF data.
  std::vector<uint8_t> Block() const {
    unsigned char* block = nullptr;
    unsigned int size = 0;
    exif_data_save_data(exif_, &block, &size);
    std::vector<uint8_t> out(block, block + size);
    std::free(block);
    return out;
  }

  // `jpeg` with the EXIF block right after the start-of-image marker.
  std::vector<uint8_t> Insert(const std::vector<uchar>& jpeg) const {
    const std::vector<uint8_t> block = Block();
    const size_t size = block.size();
    const unsigned length = size + 2;  // the segment length counts its own two bytes
    std::vector<uint8_t> out;
    out.reserve(jpeg.size() + size + 4);
    for (const uint8_t byte :
         {jpeg[0], jpeg[1], uint8_t{0xFF}, uint8_t{0xE1}, static_cast<uint8_t>(length >> 8),
          static_cast<uint8_t>(length & 0xFF)}) {
      out.push_back(byte);
    }
    out.insert(out.end(), block.begin(), block.end());
    out.insert(out.end(), jpeg.begin() + 2, jpeg.end());
    return out;
  }

 private:
  ExifEntry* Add(ExifIfd ifd, ExifTag tag, ExifFormat format) {
    ExifEntry* entry = exif_entry_new();
    entry->tag = tag;
    entry->format = format;
    entry->components = 1;
    entry->size = exif_format_get_size(format);
    entry->data = static_cast<unsigned char*>(std::calloc(1, entry->size));
    exif_content_add_entry(exif_->ifd[ifd], entry);
    exif_entry_unref(entry);  // the content holds it now
    return entry;
  }

  ExifData* exif_;
};

std::vector<uchar> EncodedTestImage(int width, int height) {
  cv::Mat image(height, width, CV_8UC3);
  cv::RNG(3).fill(image, cv::RNG::UNIFORM, 0, 256);
  std::vector<uchar> jpeg;
  EXPECT_TRUE(EncodeJpeg(image, 95, &jpeg));
  return jpeg;
}

fs::path WriteFile(const fs::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  return path;
}

TEST(Exif, FocalFrom35mmEquivalentUsesTheDiagonal) {
  ExifWriter exif;
  exif.Short(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_LENGTH_IN_35MM_FILM, 28);
  const std::vector<uint8_t> jpeg = exif.Insert(EncodedTestImage(160, 120));
  const auto focal = ExifFocalLengthPixels(jpeg.data(), jpeg.size(), 160, 120);
  ASSERT_TRUE(focal.has_value());
  EXPECT_NEAR(*focal, 28.0 * 200.0 / std::hypot(36.0, 24.0), 1e-9);
}

TEST(Exif, FocalFromFocalPlaneResolutionScaledToTheImageSize) {
  // A 4000x3000 sensor 8 mm wide (500 px/mm), lens 6 mm: 3000 px at full size; the file is a
  // 160x120 copy, so 120 px.
  ExifWriter exif;
  exif.Rational(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_LENGTH, 6, 1);
  exif.Rational(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_PLANE_X_RESOLUTION, 5000, 1);
  exif.Short(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_PLANE_RESOLUTION_UNIT, 3);  // per centimetre
  exif.Long(EXIF_IFD_EXIF, EXIF_TAG_PIXEL_X_DIMENSION, 4000);
  exif.Long(EXIF_IFD_EXIF, EXIF_TAG_PIXEL_Y_DIMENSION, 3000);
  const std::vector<uint8_t> jpeg = exif.Insert(EncodedTestImage(160, 120));
  const auto focal = ExifFocalLengthPixels(jpeg.data(), jpeg.size(), 160, 120);
  ASSERT_TRUE(focal.has_value());
  EXPECT_NEAR(*focal, 120.0, 1e-9);
}

TEST(Exif, NoFocalWithoutTagsOrWithPlaceholderValues) {
  const std::vector<uchar> plain = EncodedTestImage(160, 120);
  EXPECT_FALSE(ExifFocalLengthPixels(plain.data(), plain.size(), 160, 120).has_value());
  ExifWriter only_mm;  // a focal length in mm alone gives no pixel size
  only_mm.Rational(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_LENGTH, 6, 1);
  const std::vector<uint8_t> a = only_mm.Insert(plain);
  EXPECT_FALSE(ExifFocalLengthPixels(a.data(), a.size(), 160, 120).has_value());
  ExifWriter zero;
  zero.Rational(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_LENGTH, 0, 0);
  zero.Short(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_LENGTH_IN_35MM_FILM, 0);
  const std::vector<uint8_t> b = zero.Insert(plain);
  EXPECT_FALSE(ExifFocalLengthPixels(b.data(), b.size(), 160, 120).has_value());
}

TEST(Exif, CorruptResolutionUnitIsNoUnit) {
  // A unit of 4e9 was converted to int (undefined behaviour).
  ExifWriter exif;
  exif.Rational(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_LENGTH, 6, 1);
  exif.Rational(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_PLANE_X_RESOLUTION, 5000, 1);
  exif.Long(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_PLANE_RESOLUTION_UNIT, 4000000000u);
  const std::vector<uint8_t> jpeg = exif.Insert(EncodedTestImage(160, 120));
  EXPECT_FALSE(ExifFocalLengthPixels(jpeg.data(), jpeg.size(), 160, 120).has_value());
}

TEST(ReadPhoto, AppliesExifOrientationAndReadsFocal) {
  testing::TempDir dir("exif_orientation");
  ExifWriter exif;
  exif.Short(EXIF_IFD_0, EXIF_TAG_ORIENTATION, 6);  // stored sideways: rotate 90 degrees
  exif.Short(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_LENGTH_IN_35MM_FILM, 35);
  const fs::path path =
      WriteFile(dir.path() / "rotated.jpg", exif.Insert(EncodedTestImage(160, 120)));
  for (const ColorMode mode : {ColorMode::kColor, ColorMode::kGray}) {
    const Photo image = ReadPhoto(path, mode);
    EXPECT_EQ(image.width(), 120);
    EXPECT_EQ(image.height(), 160);
    ASSERT_TRUE(image.exif_focal_px.has_value());
    EXPECT_NEAR(*image.exif_focal_px, 35.0 * 200.0 / std::hypot(36.0, 24.0), 1e-9);
  }
}

// An iPhone's HEIC: the pixels stored sideways with HEIF's rotation property, the EXIF block
// (a metadata item, not in the file's bytes for libexif to find) stating the same orientation.
// Turned once (not again by the EXIF tag), focal length from the EXIF.
TEST(ReadPhoto, ReadsAHeicsRotationOnceAndItsExifFocal) {
  testing::TempDir dir("exif_heic");
  ExifWriter exif;
  exif.Short(EXIF_IFD_0, EXIF_TAG_ORIENTATION, 6);
  exif.Short(EXIF_IFD_EXIF, EXIF_TAG_FOCAL_LENGTH_IN_35MM_FILM, 26);
  cv::Mat stored(120, 160, CV_8UC3);
  for (int y = 0; y < stored.rows; ++y)
    for (int x = 0; x < stored.cols; ++x)
      stored.at<cv::Vec3b>(y, x) = {static_cast<uint8_t>(x), static_cast<uint8_t>(2 * y), 90};
  const std::vector<uint8_t> heic = testing::EncodeHeic(stored, 90, 6, exif.Block());
  ASSERT_FALSE(heic.empty());
  const fs::path path = WriteFile(dir.path() / "IMG_0001.HEIC", heic);
  const Photo image = ReadPhoto(path, ColorMode::kColor);
  ASSERT_EQ(image.width(), 120);
  ASSERT_EQ(image.height(), 160);
  cv::Mat upright;
  cv::rotate(stored, upright, cv::ROTATE_90_CLOCKWISE);
  EXPECT_LT(cv::norm(image.pixels, upright, cv::NORM_L1) / upright.total() / 3, 3.0);
  ASSERT_TRUE(image.exif_focal_px.has_value());
  EXPECT_NEAR(*image.exif_focal_px, 26.0 * 200.0 / std::hypot(36.0, 24.0), 1e-9);
  // Without an EXIF block: no focal prior (the file's bytes are not searched for one).
  const fs::path bare = WriteFile(dir.path() / "bare.heic", testing::EncodeHeic(stored));
  EXPECT_FALSE(ReadPhoto(bare, ColorMode::kGray).exif_focal_px.has_value());
}

// Real camera EXIF: the Sceaux photographs (Kodak) against their calibrated focal length.
TEST(ReadPhoto, ExifFocalOfRealPhotographsIsCloseToTheCalibration) {
  VARSFM_REQUIRE_SHARED_DATA(photo, "sceaux/images/100_7100.JPG");
  VARSFM_REQUIRE_SHARED_DATA(k_file, "sceaux/K.txt");
  double calibrated = 0;
  std::ifstream(k_file) >> calibrated;
  const Photo image = ReadPhoto(photo, ColorMode::kGray);
  ASSERT_TRUE(image.exif_focal_px.has_value());
  // EXIF focal lengths are nominal (rounded, before focus breathing): within 10 %.
  EXPECT_NEAR(*image.exif_focal_px / calibrated, 1.0, 0.10) << *image.exif_focal_px;
}

}  // namespace
}  // namespace varsfm
