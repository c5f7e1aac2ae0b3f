#pragma once
// Small JPEG copies of the photos for the report's table and the 3D view's camera pop-up.
#include <filesystem>
#include <optional>
#include <string>

namespace varsfm {

struct Thumbnail {
  std::string jpeg_base64;
  int width = 0;
  int height = 0;
};

// The photo at `path` downscaled (area averaging) to `width` pixels wide, or kept when it is
// narrower, as a JPEG of `quality`. Nothing when the file cannot be read or decoded: a
// thumbnail is never worth failing a report for.
std::optional<Thumbnail> MakeThumbnail(const std::filesystem::path& path, int width, int quality);

}  // namespace varsfm
