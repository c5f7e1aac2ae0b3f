#include "varsfm/image/video_keyframes.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "varsfm/image/image_file.h"
#include "varsfm/image/video_reader.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/statistics.h"

namespace varsfm {
namespace {

struct Frame {
  size_t index = 0;
  cv::Mat full;   // as decoded (BGR)
  cv::Mat small;  // grey, at most analysis_size
  double sharpness = 0;
};

cv::Mat AnalysisImage(const cv::Mat& frame, int max_size) {
  cv::Mat gray;
  if (frame.channels() == 1) {
    gray = frame;
  } else {
    cv::cvtColor(frame, gray, frame.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  }
  const double scale = static_cast<double>(max_size) / std::max(gray.cols, gray.rows);
  if (scale >= 1.0) return gray.clone();
  cv::Mat small;
  cv::resize(gray, small, cv::Size(), scale, scale, cv::INTER_AREA);
  return small;
}

// Variance of the Laplacian: high for sharp detail, low for defocus or motion blur.
double Sharpness(const cv::Mat& gray) {
  cv::Mat laplacian;
  cv::Laplacian(gray, laplacian, CV_32F);
  cv::Scalar mean, stddev;
  cv::meanStdDev(laplacian, mean, stddev);
  return stddev[0] * stddev[0];
}

// Corners of the last keyframe and their motion into later frames.
class MotionTracker {
 public:
  void SetKeyframe(const cv::Mat& small, size_t index) {
    keyframe_ = small;
    keyframe_index_ = index;
    corners_ = Corners(small);
  }

  // Whether frame `index` (`small`) has moved far enough from the keyframe to be the next one.
  bool MovedEnough(const cv::Mat& small, size_t index, const KeyframeOptions& options) const {
    if (corners_.size() < kMinCorners) {
      // The keyframe's motion cannot be measured: wait for content or for the interval.
      return index - keyframe_index_ >= static_cast<size_t>(options.featureless_interval) ||
             Corners(small).size() >= kMinCorners;
    }
    std::vector<cv::Point2f> tracked, back;
    std::vector<uchar> status, back_status;
    std::vector<float> error;
    const cv::Size window(21, 21);
    cv::calcOpticalFlowPyrLK(keyframe_, small, corners_, tracked, status, error, window, 4);
    // Forward-backward check: a track is kept only if it leads back to its corner, which
    // rejects the drifting tracks LK produces on occlusions and repeated texture.
    cv::calcOpticalFlowPyrLK(small, keyframe_, tracked, back, back_status, error, window, 4);
    std::vector<double> displacements;
    for (size_t i = 0; i < corners_.size(); ++i) {
      if (!status[i] || !back_status[i] || cv::norm(back[i] - corners_[i]) > 1.0) continue;
      displacements.push_back(cv::norm(tracked[i] - corners_[i]));
    }
    const double tracked_fraction = static_cast<double>(displacements.size()) / corners_.size();
    if (tracked_fraction < options.min_tracked) return true;
    const double diagonal = std::hypot(small.cols, small.rows);
    return Median(displacements) >= options.min_motion * diagonal;
  }

 private:
  // Fewer corners than this give no reliable median motion.
  static constexpr size_t kMinCorners = 8;

  static std::vector<cv::Point2f> Corners(const cv::Mat& small) {
    std::vector<cv::Point2f> corners;
    const double diagonal = std::hypot(small.cols, small.rows);
    cv::goodFeaturesToTrack(small, corners, 400, 0.01, 0.01 * diagonal);
    return corners;
  }

  cv::Mat keyframe_;
  size_t keyframe_index_ = 0;
  std::vector<cv::Point2f> corners_;
};

// Evenly spaced indices: `count` of `total` (count < total), first and last included.
std::vector<size_t> EvenSubsample(size_t total, size_t count) {
  std::vector<size_t> chosen;
  if (count == 1) return {0};
  for (size_t k = 0; k < count; ++k) {
    chosen.push_back(static_cast<size_t>(
        std::llround(static_cast<double>(k) * (total - 1) / static_cast<double>(count - 1))));
  }
  return chosen;
}

}  // namespace

void CheckVideoFileExists(const std::filesystem::path& video) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(video, ec))
    Fail("video {} is a folder: give a video file (a folder of photos goes to --images)",
         video.string());
  if (!fs::is_regular_file(video, ec)) Fail("video {} does not exist", video.string());
}

KeyframeSummary ExtractKeyframes(const std::filesystem::path& video,
                                 const std::filesystem::path& output_dir,
                                 const KeyframeOptions& options) {
  namespace fs = std::filesystem;
  CheckVideoFileExists(video);
  std::error_code ec;
  VideoReader capture(video);

  KeyframeSummary summary;
  std::deque<Frame> pending;  // decoded frames waiting for their look-ahead
  std::deque<double> recent;  // sharpness of the frames before pending.front()
  MotionTracker tracker;
  bool have_keyframe = false;
  bool end_of_video = false;

  auto read_frame = [&]() {
    cv::Mat decoded;
    if (!capture.Read(&decoded) || decoded.empty()) {
      end_of_video = true;
      return;
    }
    Frame frame;
    frame.index = summary.frames_read++;
    frame.small = AnalysisImage(decoded, options.analysis_size);
    frame.sharpness = Sharpness(frame.small);
    frame.full = std::move(decoded);
    pending.push_back(std::move(frame));
  };

  auto write_keyframe = [&](const Frame& frame) {
    if (summary.names.empty()) {
      fs::create_directories(output_dir, ec);
      if (ec) Fail("cannot create folder {}: {}", output_dir.string(), ec.message());
    }
    std::string name = fmt::format("frame_{:06d}.jpg", frame.index);
    const fs::path path = output_dir / name;
    ImageWriteOptions write_options;
    write_options.jpeg_quality = options.jpeg_quality;
    WriteImage(path, frame.full, write_options);
    summary.names.push_back(std::move(name));
  };

  const size_t lookahead = static_cast<size_t>(std::max(0, options.blur_frames_after));
  while (true) {
    while (!end_of_video && pending.size() <= lookahead) read_frame();
    if (pending.empty()) break;

    std::vector<double> window(recent.begin(), recent.end());
    for (const Frame& f : pending) window.push_back(f.sharpness);
    Frame frame = std::move(pending.front());
    pending.pop_front();
    recent.push_back(frame.sharpness);
    if (recent.size() > static_cast<size_t>(std::max(0, options.blur_frames_before))) {
      recent.pop_front();
    }

    if (frame.sharpness < options.blur_ratio * Median(window)) {
      ++summary.frames_blurred;
      debug("video {}: frame {} is blurred, dropped", video.filename().string(), frame.index);
      continue;
    }
    if (!have_keyframe || tracker.MovedEnough(frame.small, frame.index, options)) {
      write_keyframe(frame);
      tracker.SetKeyframe(frame.small, frame.index);
      have_keyframe = true;
    }
  }
  if (summary.frames_read == 0) Fail("cannot decode any frame of video {}", video.string());
  const double announced = capture.FrameCount();
  if (announced > 0 && announced < 1e12) {  // NaN, 0 and nonsense: unknown
    summary.frames_announced = static_cast<size_t>(announced);
    if (DecodingStoppedShort(summary.frames_read, summary.frames_announced))
      warn(
          "video {}: decoding stopped at frame {} of the {} its container announces (truncated "
          "or damaged file?); keyframes come from the frames decoded",
          video.string(), summary.frames_read, summary.frames_announced);
  }

  const size_t max_frames = static_cast<size_t>(std::max(0, options.max_frames));
  if (max_frames > 0 && summary.names.size() > max_frames) {
    // Keyframes are written as they are found (a video may not fit in memory), so the ones
    // the cap leaves out are removed afterwards.
    std::vector<std::string> kept;
    size_t next = 0;
    const std::vector<size_t> chosen = EvenSubsample(summary.names.size(), max_frames);
    for (size_t i = 0; i < summary.names.size(); ++i) {
      if (next < chosen.size() && chosen[next] == i) {
        kept.push_back(summary.names[i]);
        ++next;
      } else {
        fs::remove(output_dir / summary.names[i], ec);
      }
    }
    summary.names = std::move(kept);
  }
  return summary;
}

void KeyframeOptions::Check() const {
  CheckNonNegative("blur_ratio", blur_ratio);
  CheckNonNegative("blur_frames_before", blur_frames_before);
  CheckNonNegative("blur_frames_after", blur_frames_after);
  CheckNonNegative("min_motion", min_motion);
  CheckFraction("min_tracked", min_tracked);
  CheckAtLeast("featureless_interval", featureless_interval, 1);
  CheckNonNegative("--max-frames", max_frames);
  CheckAtLeast("analysis_size", analysis_size, 16);
  CheckInRange("jpeg_quality", jpeg_quality, 1, 100);
}

}  // namespace varsfm
