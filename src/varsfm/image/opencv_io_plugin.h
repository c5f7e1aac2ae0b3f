#pragma once
// Loading the OpenCV I/O plug-in (libvarsfm_opencv_io.so, see plugin/opencv_io_plugin_api.h):
// the formats without a direct codec and video decoding. Loaded with dlopen on first use, so
// runs that only see JPEG and PNG never pay for OpenCV's imgcodecs/videoio libraries.
#include <string>

#include "varsfm/image/plugin/opencv_io_plugin_api.h"

namespace varsfm {

// The plug-in's file name (its folder is searched as LoadOpenCvIoPlugin says).
inline constexpr const char* kOpenCvIoPluginFile = "libvarsfm_opencv_io.so";

struct OpenCvIoPlugin {
  decltype(&varsfm_opencv_io_decode) decode = nullptr;
  decltype(&varsfm_opencv_io_write) write = nullptr;
  decltype(&varsfm_opencv_io_video_open) video_open = nullptr;
  decltype(&varsfm_opencv_io_video_read) video_read = nullptr;
  decltype(&varsfm_opencv_io_video_get) video_get = nullptr;
  decltype(&varsfm_opencv_io_video_close) video_close = nullptr;
};

// The plug-in, loaded on the first call from, in order: the folder of the running executable
// (the build folder, or wherever varsfm was copied with it), then the build folder this library
// was compiled for (so test programs in build/tests/<module>/ find it). Thread-safe; the library
// stays loaded until the process exits. Returns nullptr when no candidate could be loaded, with
// `*why` saying what was tried and why it failed (one line).
const OpenCvIoPlugin* LoadOpenCvIoPlugin(std::string* why);

// The plug-in, or throws varsfm::Error "`failure`: `needs` the OpenCV I/O plug-in
// (libvarsfm_opencv_io.so), not found: <why>", e.g. failure "cannot read a.tif", needs
// "format needs".
const OpenCvIoPlugin& RequireOpenCvIoPlugin(const std::string& failure, const std::string& needs);

}  // namespace varsfm
