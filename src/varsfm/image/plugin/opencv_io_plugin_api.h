#pragma once
// The C interface of the OpenCV I/O plug-in (libvarsfm_opencv_io.so), shared by the plug-in
// and its loader (image/opencv_io_plugin.h).
//
// Why a plug-in: OpenCV's imgcodecs and videoio drag in ~210 shared libraries (GDAL, GStreamer,
// FFmpeg, ...) whose loading cost every varsfm start 0.2 s, more than a small map run takes.
// JPEG and PNG, nearly all varsfm reads and writes, have direct codecs (jpeg_codec.h,
// png_codec.h); the rarer formats (TIFF, BMP, WebP, PNM, ...) and video go through this
// plug-in, which the loader dlopens on first use only.
//
// The functions are extern "C" so dlsym finds them by plain name. cv::Mat crosses the
// boundary by pointer: both sides use the same shared opencv_core. No C++ exception crosses it:
// failures return 0 / nullptr and a message in `error` (at most `error_size` bytes, with its
// terminating NUL).
#include <cstddef>

#include <opencv2/core.hpp>

// Bumped whenever a signature below changes; the loader refuses a plug-in of another version.
#define VARSFM_OPENCV_IO_ABI_VERSION 1

// Properties of an open video (our own numbers, so the main code needs no videoio header).
enum VarsfmVideoProperty {
  kVarsfmVideoFrameCount = 0,
  kVarsfmVideoFps = 1,
  kVarsfmVideoWidth = 2,
  kVarsfmVideoHeight = 3,
};

extern "C" {

int varsfm_opencv_io_abi_version();

// cv::imdecode(`data`, `imread_flags`) into *image; 1 on success, 0 when the data is not an
// image OpenCV can decode.
int varsfm_opencv_io_decode(const unsigned char* data, size_t size, int imread_flags,
                            cv::Mat* image, char* error, size_t error_size);

// cv::imwrite(`path`, *image, params) (`params`: `num_params` ints, cv::IMWRITE_* pairs);
// 1 on success, 0 otherwise (e.g. an extension OpenCV has no encoder for).
int varsfm_opencv_io_write(const char* path, const cv::Mat* image, const int* params,
                           size_t num_params, char* error, size_t error_size);

// Opens `path` with cv::VideoCapture; an opaque handle, or nullptr when it cannot be opened.
void* varsfm_opencv_io_video_open(const char* path, char* error, size_t error_size);
// The next frame (BGR) into *frame; 1, or 0 at the end of the video or on a decoding error.
int varsfm_opencv_io_video_read(void* video, cv::Mat* frame);
// A VarsfmVideoProperty of the video, or 0 when unknown.
double varsfm_opencv_io_video_get(void* video, int property);
void varsfm_opencv_io_video_close(void* video);

}  // extern "C"
