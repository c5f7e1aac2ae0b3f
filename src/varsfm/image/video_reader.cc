#include "varsfm/image/video_reader.h"

#include "varsfm/image/opencv_io_plugin.h"
#include "varsfm/util/error.h"

namespace varsfm {

VideoReader::VideoReader(const std::filesystem::path& video)
    : plugin_(
          &RequireOpenCvIoPlugin("cannot read video " + video.string(), "decoding video needs")),
      capture_(nullptr) {
  char error[512] = "";
  capture_ = plugin_->video_open(video.c_str(), error, sizeof(error));
  if (capture_ == nullptr) Fail("cannot open video {} ({})", video.string(), error);
}

VideoReader::~VideoReader() { plugin_->video_close(capture_); }

bool VideoReader::Read(cv::Mat* frame) { return plugin_->video_read(capture_, frame) != 0; }

double VideoReader::FrameCount() const {
  return plugin_->video_get(capture_, kVarsfmVideoFrameCount);
}

double VideoReader::FramesPerSecond() const {
  return plugin_->video_get(capture_, kVarsfmVideoFps);
}

}  // namespace varsfm
