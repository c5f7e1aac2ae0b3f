#pragma once
// Reading and writing image files, pixels only. JPEG and PNG, nearly everything varsfm reads and
// writes, are decoded and encoded directly (jpeg_codec.h with libjpeg-turbo, png_codec.h with
// libpng), giving the same pixels and files as OpenCV's imgcodecs did; HEIF (HEIC, AVIF), which
// OpenCV does not read, is decoded with libheif (heif_codec.h); every other format (TIFF, BMP,
// WebP, PNM, ...) goes through the OpenCV I/O plug-in (opencv_io_plugin.h), loaded on first use.
// This keeps imgcodecs and videoio, and the ~210 shared libraries they pull in (GDAL, GStreamer,
// FFmpeg, ...), out of every start of the varsfm binary.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace varsfm {

enum class ColorMode { kGray, kColor };

// The most pixels DecodeImage decodes (2^28, 268 Mpx: 805 MB as BGR), above any camera's; a
// larger size field is taken for a corrupt or malicious file and refused before allocation.
inline constexpr uint64_t kMaxImagePixels = uint64_t{1} << 28;

// Throws varsfm::Error (one line naming `path`) when `width` x `height`, as a file declares them,
// is more than kMaxImagePixels: each decoder checks before it allocates.
void RequireDecodablePixelCount(const std::filesystem::path& path, uint64_t width, uint64_t height);

// The bytes of `path`. Throws varsfm::Error (one line naming the file) when it cannot be read
// or is empty.
std::vector<uint8_t> ReadImageFile(const std::filesystem::path& path);

// Decodes the contents `bytes` of image file `path` (named in errors) into the pixels
// cv::imread(IMREAD_GRAYSCALE / IMREAD_COLOR) gave: 8-bit, 1 or 3 (BGR) channels, upright
// (EXIF orientation applied; HEIF's own rotation and mirror). Throws varsfm::Error (one line naming
// the file) when it is not a decodable image, is a truncated JPEG (which libjpeg would silently
// grey-fill), declares more than kMaxImagePixels (or a PNG more than its data can hold), or needs
// the OpenCV I/O plug-in and that cannot be loaded.
cv::Mat DecodeImage(const std::filesystem::path& path, const std::vector<uint8_t>& bytes,
                    ColorMode mode);

// The extension of `path` in lower case, with its dot (".jpg"; "" when it has none): the format
// a file name claims.
std::string LowerCaseExtension(const std::filesystem::path& path);

// ReadImageFile then DecodeImage.
cv::Mat ReadImagePixels(const std::filesystem::path& path, ColorMode mode = ColorMode::kColor);

struct ImageWriteOptions {
  int jpeg_quality = 95;  // 0-100; OpenCV's default
};

// Writes `image` (8-bit grey, BGR or BGRA; PNG also 16-bit) to `path`, in the format its
// extension names (case-insensitive): .png and .jpg/.jpeg directly, others through the OpenCV
// I/O plug-in. Does not create folders. Throws varsfm::Error (one line naming the file) when
// the file cannot be written.
void WriteImage(const std::filesystem::path& path, const cv::Mat& image,
                const ImageWriteOptions& options = {});

}  // namespace varsfm
