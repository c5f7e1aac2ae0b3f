#pragma once
// Reading photographs (JPEG, PNG, TIFF, BMP) through OpenCV, upright (EXIF orientation applied)
// and with the EXIF focal length as an optional prior.
#include <filesystem>
#include <optional>

#include <opencv2/core.hpp>

namespace varsfm {

enum class ColorMode { kGray, kColor };

struct Image {
  cv::Mat pixels;                       // 8-bit, 1 (kGray) or 3 (kColor, BGR) channels, upright
  std::optional<double> exif_focal_px;  // see image/exif.h

  int width() const { return pixels.cols; }
  int height() const { return pixels.rows; }
};

// Reads `path`. Throws varsfm::Error (one line naming the file) when the file cannot be read,
// is not a decodable image, or is a truncated JPEG (which OpenCV would silently grey-fill).
Image ReadImage(const std::filesystem::path& path, ColorMode mode = ColorMode::kColor);

}  // namespace varsfm
