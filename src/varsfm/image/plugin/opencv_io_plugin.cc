// The OpenCV I/O plug-in: imgcodecs and videoio behind the C interface of
// opencv_io_plugin_api.h (see there for why this is a separately loaded library).
#include "varsfm/image/plugin/opencv_io_plugin_api.h"

#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iterator>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

extern "C" {
#include <libavutil/log.h>
}

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <opencv2/videoio/registry.hpp>

#define VARSFM_EXPORT __attribute__((visibility("default")))

namespace {

void SetError(char* error, size_t error_size, const char* message) {
  if (error == nullptr || error_size == 0) return;
  std::strncpy(error, message, error_size - 1);
  error[error_size - 1] = '\0';
}

// OpenCV messages can span lines; the loader's users print one line.
void SetException(char* error, size_t error_size, const std::exception& e) {
  const cv::Exception* cv_error = dynamic_cast<const cv::Exception*>(&e);
  std::string message = cv_error != nullptr ? cv_error->err : std::string(e.what());
  for (char& c : message)
    if (c == '\n' || c == '\r') c = ' ';
  SetError(error, error_size, message.c_str());
}

// FFmpeg's messages. Its default logger prints each to stderr as it comes ("[mov,mp4,m4a,3gp,3g2,
// mj2 @ 0x...] moov atom not found" above varsfm's own error); kept here instead, the last error
// completes the one-line error of a video that cannot be opened. Those while decoding (a damaged
// frame) are dropped: the keyframe summary reports the frames read against those announced.
std::mutex ffmpeg_error_mutex;
std::string ffmpeg_error;

void KeepFfmpegError(void* /*context*/, int level, const char* format, va_list args) {
  if (level > AV_LOG_ERROR) return;
  char line[256];
  std::vsnprintf(line, sizeof(line), format, args);
  std::string message(line);
  while (!message.empty() && (message.back() == '\n' || message.back() == '\r' ||
                              message.back() == ' ' || message.back() == '.'))
    message.pop_back();
  if (message.empty()) return;
  const std::lock_guard<std::mutex> lock(ffmpeg_error_mutex);
  ffmpeg_error = std::move(message);
}

std::string TakeFfmpegError() {
  const std::lock_guard<std::mutex> lock(ffmpeg_error_mutex);
  return std::exchange(ffmpeg_error, std::string());
}

}  // namespace

extern "C" {

VARSFM_EXPORT int varsfm_opencv_io_abi_version() { return VARSFM_OPENCV_IO_ABI_VERSION; }

VARSFM_EXPORT int varsfm_opencv_io_decode(const unsigned char* data, size_t size, int imread_flags,
                                          cv::Mat* image, char* error, size_t error_size) {
  try {
    // imdecode does not write to its input; the Mat only wraps the caller's bytes.
    const cv::Mat bytes(1, static_cast<int>(size), CV_8U, const_cast<unsigned char*>(data));
    *image = cv::imdecode(bytes, imread_flags);
    if (image->empty()) SetError(error, error_size, "OpenCV cannot decode it");
    return image->empty() ? 0 : 1;
  } catch (const std::exception& e) {  // OpenCV throws on some corrupt files
    image->release();
    SetException(error, error_size, e);
    return 0;
  }
}

VARSFM_EXPORT int varsfm_opencv_io_write(const char* path, const cv::Mat* image, const int* params,
                                         size_t num_params, char* error, size_t error_size) {
  try {
    const std::vector<int> param_list(params, params + num_params);
    if (cv::imwrite(path, *image, param_list)) return 1;
    SetError(error, error_size, "OpenCV cannot write it");
  } catch (const std::exception& e) {  // e.g. an extension OpenCV has no encoder for
    SetException(error, error_size, e);
  }
  return 0;
}

VARSFM_EXPORT void* varsfm_opencv_io_video_open(const char* path, char* error, size_t error_size) {
  try {
    // OpenCV leaves FFmpeg's logger alone unless OPENCV_FFMPEG_DEBUG or _LOGLEVEL is set.
    static std::once_flag logger_set;
    std::call_once(logger_set, [] { av_log_set_callback(KeepFfmpegError); });
    TakeFfmpegError();
    // FFmpeg reads nearly every container; asking for it alone also keeps OpenCV from probing
    // GStreamer and image sequences, which print noise for a file that is not a video.
    const bool has_ffmpeg = cv::videoio_registry::hasBackend(cv::CAP_FFMPEG);
    auto capture =
        std::make_unique<cv::VideoCapture>(path, has_ffmpeg ? cv::CAP_FFMPEG : cv::CAP_ANY);
    if (capture->isOpened()) return capture.release();
    const std::string reason = TakeFfmpegError();
    SetError(error, error_size,
             reason.empty() ? "FFmpeg cannot open it as a video" : ("FFmpeg: " + reason).c_str());
  } catch (const std::exception& e) {
    SetException(error, error_size, e);
  }
  return nullptr;
}

VARSFM_EXPORT int varsfm_opencv_io_video_read(void* video, cv::Mat* frame) {
  try {
    return static_cast<cv::VideoCapture*>(video)->read(*frame) && !frame->empty() ? 1 : 0;
  } catch (const std::exception&) {
    frame->release();
    return 0;
  }
}

VARSFM_EXPORT double varsfm_opencv_io_video_get(void* video, int property) {
  static constexpr int kOpenCvProperty[] = {cv::CAP_PROP_FRAME_COUNT, cv::CAP_PROP_FPS,
                                            cv::CAP_PROP_FRAME_WIDTH, cv::CAP_PROP_FRAME_HEIGHT};
  if (property < 0 || property >= static_cast<int>(std::size(kOpenCvProperty))) return 0;
  try {
    return static_cast<cv::VideoCapture*>(video)->get(kOpenCvProperty[property]);
  } catch (const std::exception&) {
    return 0;
  }
}

VARSFM_EXPORT void varsfm_opencv_io_video_close(void* video) {
  delete static_cast<cv::VideoCapture*>(video);
}

}  // extern "C"
