#include "varsfm/image/raw_codec.h"

#include <algorithm>
#include <array>
#include <memory>

#include <libraw/libraw.h>
#include <opencv2/imgproc.hpp>

namespace varsfm {
namespace {

// LibRaw's processor (its state is large: on the heap), the file's metadata read; null when
// LibRaw does not read `data`. LibRaw reads the buffer in place: `data` must outlive it.
std::unique_ptr<LibRaw> OpenRaw(const uint8_t* data, size_t size) {
  auto raw = std::make_unique<LibRaw>();
  if (raw->open_buffer(const_cast<uint8_t*>(data), size) != LIBRAW_SUCCESS) return nullptr;
  return raw;
}

}  // namespace

bool IsRawPhotoName(const std::filesystem::path& path) {
  static constexpr std::array<const char*, 10> kExtensions = {
      ".dng", ".cr2", ".cr3", ".nef", ".arw", ".raf", ".orf", ".rw2", ".pef", ".srw"};
  const std::string ext = LowerCaseExtension(path);
  return std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

cv::Mat DecodeRaw(const std::filesystem::path& path, const uint8_t* data, size_t size,
                  ColorMode mode) {
  const std::unique_ptr<LibRaw> raw = OpenRaw(data, size);
  if (!raw) return {};
  const uint64_t width = raw->imgdata.sizes.raw_width, height = raw->imgdata.sizes.raw_height;
  RequireDecodablePixelCount(path, width, height);
  // dcraw's defaults but the camera's white balance (-w) and 8 bits: a photo as the camera's
  // own JPEG would roughly show it, which is what features and texture want.
  raw->imgdata.params.use_camera_wb = 1;
  raw->imgdata.params.output_bps = 8;
  if (raw->unpack() != LIBRAW_SUCCESS || raw->dcraw_process() != LIBRAW_SUCCESS) return {};
  int error = 0;
  std::unique_ptr<libraw_processed_image_t, void (*)(libraw_processed_image_t*)> image(
      raw->dcraw_make_mem_image(&error), LibRaw::dcraw_clear_mem);
  if (!image || error != LIBRAW_SUCCESS || image->type != LIBRAW_IMAGE_BITMAP || image->bits != 8 ||
      (image->colors != 3 && image->colors != 1))
    return {};
  const cv::Mat view(image->height, image->width, image->colors == 3 ? CV_8UC3 : CV_8UC1,
                     image->data);
  cv::Mat pixels;
  if (image->colors == 1 && mode == ColorMode::kGray)
    pixels = view.clone();
  else if (image->colors == 1)
    cv::cvtColor(view, pixels, cv::COLOR_GRAY2BGR);
  else
    cv::cvtColor(view, pixels, mode == ColorMode::kGray ? cv::COLOR_RGB2GRAY : cv::COLOR_RGB2BGR);
  return pixels;
}

std::optional<double> RawFocalLength35mm(const uint8_t* data, size_t size) {
  const std::unique_ptr<LibRaw> raw = OpenRaw(data, size);
  if (!raw || raw->imgdata.lens.FocalLengthIn35mmFormat == 0) return std::nullopt;
  return static_cast<double>(raw->imgdata.lens.FocalLengthIn35mmFormat);
}

}  // namespace varsfm
