#pragma once
// Reading photographs for feature extraction: the pixels, upright (EXIF orientation applied),
// with the EXIF focal length as an optional prior. The decoding itself, and writing images,
// are in image_file.h (JPEG and PNG directly, other formats through the OpenCV I/O plug-in).
#include <filesystem>
#include <optional>

#include <opencv2/core.hpp>

#include "varsfm/image/image_file.h"

namespace varsfm {

// A decoded photograph (not to be confused with scene/reconstruction.h's Image, a view of the
// sparse model).
struct Photo {
  cv::Mat pixels;                       // 8-bit, 1 (kGray) or 3 (kColor, BGR) channels, upright
  std::optional<double> exif_focal_px;  // see image/exif.h

  int width() const { return pixels.cols; }
  int height() const { return pixels.rows; }
};

// Reads `path` (see DecodeImage in image_file.h for the pixels). Throws varsfm::Error (one line
// naming the file) when the file cannot be read, is not a decodable image, is a truncated JPEG
// (which libjpeg would silently grey-fill), or needs the OpenCV I/O plug-in and that cannot be
// loaded.
Photo ReadPhoto(const std::filesystem::path& path, ColorMode mode = ColorMode::kColor);

}  // namespace varsfm
