#include "varsfm/image/image_io.h"

#include <fstream>
#include <iterator>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "varsfm/image/exif.h"
#include "varsfm/image/jpeg_check.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

std::vector<uint8_t> ReadFileBytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) Fail("cannot open image {}", path.string());
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)),
                             std::istreambuf_iterator<char>());
  if (file.bad()) Fail("cannot read image {}", path.string());
  return bytes;
}

}  // namespace

Image ReadImage(const std::filesystem::path& path, ColorMode mode) {
  // The bytes are read once and shared by the JPEG check, the EXIF parser and the decoder.
  std::vector<uint8_t> bytes = ReadFileBytes(path);
  if (bytes.empty()) Fail("image {} is empty", path.string());
  if (LooksLikeJpeg(bytes.data(), bytes.size()) && !IsCompleteJpeg(bytes.data(), bytes.size())) {
    Fail("image {} is a truncated or corrupt JPEG", path.string());
  }

  Image image;
  // Without IMREAD_IGNORE_ORIENTATION, OpenCV rotates/flips by the EXIF orientation tag.
  const int flags = mode == ColorMode::kGray ? cv::IMREAD_GRAYSCALE : cv::IMREAD_COLOR;
  try {
    image.pixels =
        cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U, bytes.data()), flags);
  } catch (const cv::Exception&) {
    image.pixels.release();  // OpenCV throws on some corrupt files instead of returning empty
  }
  if (image.pixels.empty()) Fail("image {} is not a decodable image", path.string());
  image.exif_focal_px =
      ExifFocalLengthPixels(bytes.data(), bytes.size(), image.width(), image.height());
  return image;
}

}  // namespace varsfm
