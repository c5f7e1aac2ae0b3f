#include "varsfm/image/jpeg_codec.h"

#include <turbojpeg.h>

#include <algorithm>
#include <memory>

namespace varsfm {
namespace {

struct TjDeleter {
  void operator()(void* handle) const { tjDestroy(handle); }
};
using TjHandle = std::unique_ptr<void, TjDeleter>;

struct TjBufferDeleter {
  void operator()(unsigned char* buffer) const { tjFree(buffer); }
};

// tjDecompress2 also reports warnings (e.g. "extraneous bytes before marker", common in camera
// files) as failures. libjpeg under OpenCV ignores them and so do we: the pixels are complete
// (truncation is caught beforehand by IsCompleteJpeg).
bool DecodeSucceeded(int status, void* handle) {
  return status == 0 || tjGetErrorCode(handle) == TJERR_WARNING;
}

}  // namespace

std::optional<cv::Mat> DecodeJpeg(const uint8_t* data, size_t size, ColorMode mode) {
  TjHandle handle(tjInitDecompress());
  if (!handle) return cv::Mat();
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(handle.get(), data, static_cast<unsigned long>(size), &width, &height,
                          &subsampling, &colorspace) != 0 ||
      width <= 0 || height <= 0) {
    return cv::Mat();
  }
  if (colorspace == TJCS_CMYK || colorspace == TJCS_YCCK) return std::nullopt;

  const bool gray = mode == ColorMode::kGray;
  cv::Mat pixels(height, width, gray ? CV_8UC1 : CV_8UC3);
  // Flags 0: accurate DCT and fancy upsampling, libjpeg's defaults, which OpenCV keeps.
  const int status =
      tjDecompress2(handle.get(), data, static_cast<unsigned long>(size), pixels.data, width,
                    static_cast<int>(pixels.step[0]), height, gray ? TJPF_GRAY : TJPF_BGR, 0);
  if (!DecodeSucceeded(status, handle.get())) return cv::Mat();
  return pixels;
}

bool JpegDimensions(const uint8_t* data, size_t size, int* width, int* height) {
  TjHandle handle(tjInitDecompress());
  int subsampling = 0, colorspace = 0;
  return handle && tjDecompressHeader3(handle.get(), data, static_cast<unsigned long>(size), width,
                                       height, &subsampling, &colorspace) == 0;
}

bool EncodeJpeg(const cv::Mat& image, int quality, std::vector<uint8_t>* jpeg) {
  if (image.depth() != CV_8U || image.empty()) return false;
  int pixel_format = 0;
  switch (image.channels()) {
    case 1:
      pixel_format = TJPF_GRAY;
      break;
    case 3:
      pixel_format = TJPF_BGR;
      break;
    case 4:
      pixel_format = TJPF_BGRX;  // OpenCV drops the alpha channel too
      break;
    default:
      return false;
  }
  TjHandle handle(tjInitCompress());
  if (!handle) return false;
  unsigned char* buffer = nullptr;
  unsigned long buffer_size = 0;
  // TurboJPEG picks the fast DCT below quality 96; ACCURATEDCT keeps libjpeg's default (islow),
  // which OpenCV uses, so the files match what cv::imwrite wrote.
  const int status = tjCompress2(handle.get(), image.data, image.cols,
                                 static_cast<int>(image.step[0]), image.rows, pixel_format, &buffer,
                                 &buffer_size, image.channels() == 1 ? TJSAMP_GRAY : TJSAMP_420,
                                 std::clamp(quality, 0, 100), TJFLAG_ACCURATEDCT);
  std::unique_ptr<unsigned char, TjBufferDeleter> owned(buffer);
  if (status != 0) return false;
  jpeg->assign(buffer, buffer + buffer_size);
  return true;
}

}  // namespace varsfm
