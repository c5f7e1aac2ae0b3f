#pragma once
// Reading the frames of a video file. Decoding goes through the OpenCV I/O plug-in
// (image/opencv_io_plugin.h: OpenCV's videoio, FFmpeg first), loaded when the first video is
// opened, so commands that never see a video do not load FFmpeg and GStreamer.
#include <filesystem>

#include <opencv2/core.hpp>

namespace varsfm {

struct OpenCvIoPlugin;

class VideoReader {
 public:
  // Opens `video`. Throws varsfm::Error (one line naming the file) when it cannot be opened or
  // the plug-in is missing.
  explicit VideoReader(const std::filesystem::path& video);
  ~VideoReader();
  VideoReader(const VideoReader&) = delete;
  VideoReader& operator=(const VideoReader&) = delete;

  // The next frame (8-bit BGR) into *frame; false at the end of the video (or on a frame that
  // cannot be decoded, which ends reading as cv::VideoCapture does).
  bool Read(cv::Mat* frame);

  // What the container says; 0 when unknown. The frame count is an estimate for some formats.
  double FrameCount() const;
  double FramesPerSecond() const;

 private:
  const OpenCvIoPlugin* plugin_;
  void* capture_;  // owned, closed by the plug-in
};

}  // namespace varsfm
