#include "varsfm/image/image_file.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "varsfm/image/exif.h"
#include "varsfm/image/heif_codec.h"
#include "varsfm/image/jpeg_check.h"
#include "varsfm/image/jpeg_codec.h"
#include "varsfm/image/opencv_io_plugin.h"
#include "varsfm/image/orientation.h"
#include "varsfm/image/png_codec.h"
#include "varsfm/image/raw_codec.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// cv::IMREAD_GRAYSCALE / cv::IMREAD_COLOR and cv::IMWRITE_JPEG_QUALITY (imgcodecs.hpp, a
// header of the library this code no longer links; the values are OpenCV's stable API).
constexpr int kImreadGrayscale = 0;
constexpr int kImreadColor = 1;
constexpr int kImwriteJpegQuality = 1;

// Any format but JPEG and PNG: OpenCV decodes it, EXIF orientation included.
cv::Mat DecodeWithPlugin(const std::filesystem::path& path, const std::vector<uint8_t>& bytes,
                         ColorMode mode) {
  const OpenCvIoPlugin& plugin =
      RequireOpenCvIoPlugin("cannot read " + path.string(), "format needs");
  cv::Mat pixels;
  char error[512] = "";
  const int flags = mode == ColorMode::kGray ? kImreadGrayscale : kImreadColor;
  if (!plugin.decode(bytes.data(), bytes.size(), flags, &pixels, error, sizeof(error)))
    pixels.release();
  return pixels;
}

// Refuses a JPEG or PNG whose declared size is more than kMaxImagePixels, or (PNG) more than
// its bytes can expand to: deflate expands at most 1032:1 (a 258-byte match in two 1-bit codes,
// RFC 1951) and a pixel takes at least one bit, so a PNG holds at most 8 * 1032 pixels per byte.
// Either way a few bytes could otherwise make the decoder allocate gigabytes.
void RequirePlausibleSize(const std::filesystem::path& path, const std::vector<uint8_t>& bytes,
                          bool jpeg) {
  uint64_t width = 0, height = 0;
  if (int w = 0, h = 0; jpeg && JpegDimensions(bytes.data(), bytes.size(), &w, &h)) {
    width = static_cast<uint64_t>(std::max(w, 0));
    height = static_cast<uint64_t>(std::max(h, 0));
  } else if (uint32_t w = 0, h = 0; !jpeg && PngDimensions(bytes.data(), bytes.size(), &w, &h)) {
    width = w;
    height = h;
    if (width * height > 8 * 1032 * uint64_t{bytes.size()})
      Fail("image {} declares {} x {} pixels, more than its {} bytes can hold (corrupt PNG)",
           path.string(), width, height, bytes.size());
  }
  RequireDecodablePixelCount(path, width, height);
}

}  // namespace

void RequireDecodablePixelCount(const std::filesystem::path& path, uint64_t width,
                                uint64_t height) {
  if (width * height > kMaxImagePixels)
    Fail("image {} is {} x {} pixels, more than the {} varsfm decodes", path.string(), width,
         height, kMaxImagePixels);
}

std::string LowerCaseExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

std::vector<uint8_t> ReadImageFile(const std::filesystem::path& path) {
  std::error_code ec;
  // A folder opens as a stream, and the first read of the iterators below throws
  // std::ios_base::failure (the stream's own extractors would only set badbit).
  if (std::filesystem::is_directory(path, ec)) Fail("image {} is a folder", path.string());
  std::ifstream file(path, std::ios::binary);
  if (!file) Fail("cannot open image {}", path.string());
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)),
                             std::istreambuf_iterator<char>());
  if (file.bad()) Fail("cannot read image {}", path.string());
  if (bytes.empty()) Fail("image {} is empty", path.string());
  return bytes;
}

cv::Mat DecodeImage(const std::filesystem::path& path, const std::vector<uint8_t>& bytes,
                    ColorMode mode) {
  const bool jpeg = LooksLikeJpeg(bytes.data(), bytes.size());
  if (jpeg && !IsCompleteJpeg(bytes.data(), bytes.size())) {
    Fail("image {} is a truncated or corrupt JPEG", path.string());
  }
  RequirePlausibleSize(path, bytes, jpeg);
  std::optional<cv::Mat> direct;
  int orientation = 1;
  if (jpeg) {
    direct = DecodeJpeg(bytes.data(), bytes.size(), mode);  // nothing for CMYK: OpenCV does it
    if (direct && !direct->empty()) orientation = ExifOrientation(bytes.data(), bytes.size());
  } else if (LooksLikePng(bytes.data(), bytes.size())) {
    std::vector<uint8_t> exif;
    direct = DecodePng(bytes.data(), bytes.size(), mode, &exif);
    if (!exif.empty()) {
      exif.insert(exif.begin(), kExifHeader, kExifHeader + sizeof(kExifHeader));
      orientation = ExifOrientation(exif.data(), exif.size());
    }
  } else if (IsRawPhotoName(path)) {
    direct = DecodeRaw(path, bytes.data(), bytes.size(), mode);  // upright as developed
  } else if (LooksLikeHeif(bytes.data(), bytes.size())) {
    direct = DecodeHeif(path, bytes.data(), bytes.size(), mode);  // upright as decoded
  }
  cv::Mat pixels;
  if (direct) {
    // As cv::imread: the EXIF orientation (JPEG APP1, PNG eXIf chunk) turns the image upright.
    // (HEIF's and raw files' orientations are applied by their decoders.)
    pixels = std::move(*direct);
    if (!pixels.empty()) ApplyExifOrientation(orientation, &pixels);
  } else {
    pixels = DecodeWithPlugin(path, bytes, mode);
  }
  if (pixels.empty()) Fail("image {} is not a decodable image", path.string());
  return pixels;
}

cv::Mat ReadImagePixels(const std::filesystem::path& path, ColorMode mode) {
  return DecodeImage(path, ReadImageFile(path), mode);
}

void WriteImage(const std::filesystem::path& path, const cv::Mat& image,
                const ImageWriteOptions& options) {
  const std::string extension = LowerCaseExtension(path);
  const bool jpeg = extension == ".jpg" || extension == ".jpeg" || extension == ".jpe";
  std::vector<uint8_t> bytes;
  bool encoded = false;
  if (extension == ".png") {
    encoded = EncodePng(image, &bytes);
  } else if (jpeg) {
    encoded = EncodeJpeg(image, options.jpeg_quality, &bytes);
  }
  if (encoded) {
    WriteBytesAtomically(path, bytes);
    return;
  }
  // Other formats, and image types the direct encoders do not take (OpenCV converts them).
  const OpenCvIoPlugin& plugin =
      RequireOpenCvIoPlugin("cannot write image " + path.string(), "format needs");
  // The quality is a JPEG setting: other encoders (JPEG 2000) warn on stderr about it.
  const int params[] = {kImwriteJpegQuality, options.jpeg_quality};
  WriteFileViaTemporary(path, [&](const std::filesystem::path& tmp) {
    char error[512] = "";
    if (!plugin.write(tmp.c_str(), &image, params, jpeg ? std::size(params) : 0, error,
                      sizeof(error)))
      Fail("cannot write image {}: {}", path.string(), error);
  });
}

}  // namespace varsfm
