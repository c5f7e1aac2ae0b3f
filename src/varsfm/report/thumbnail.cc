#include "varsfm/report/thumbnail.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "varsfm/image/image_file.h"
#include "varsfm/image/jpeg_codec.h"
#include "varsfm/report/base64.h"

namespace varsfm {

std::optional<Thumbnail> MakeThumbnail(const std::filesystem::path& path, int width, int quality) {
  cv::Mat photo;
  try {
    photo = ReadImagePixels(path, ColorMode::kColor);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (photo.empty()) return std::nullopt;
  cv::Mat small = photo;
  if (photo.cols > width) {
    const int height = std::max(
        1, static_cast<int>(std::lround(static_cast<double>(photo.rows) * width / photo.cols)));
    cv::resize(photo, small, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  }
  std::vector<uint8_t> jpeg;
  if (!EncodeJpeg(small, quality, &jpeg)) return std::nullopt;
  return Thumbnail{Base64Encode(jpeg), small.cols, small.rows};
}

}  // namespace varsfm
