#pragma once
// Keyframe selection from a video: sharp frames, spaced so that consecutive keyframes overlap
// but show the scene from usefully different positions. The keyframes are written as JPEG files
// and are then treated like photographs.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace varsfm {

struct KeyframeOptions {
  // A frame is blurred (dropped) when its sharpness, the variance of the Laplacian, is below
  // blur_ratio times the median sharpness of the frames around it.
  double blur_ratio = 0.5;
  // The median runs over this many frames before and after the frame (the look-ahead lets the
  // very first frames be judged too).
  int blur_frames_before = 20;
  int blur_frames_after = 8;
  // A sharp frame becomes a keyframe when the corners tracked from the last keyframe moved by a
  // median of at least min_motion times the image diagonal...
  double min_motion = 0.06;
  // ...or when fewer than min_tracked of those corners can still be tracked (little overlap
  // left, e.g. fast motion or a rotation in place).
  double min_tracked = 0.5;
  // When the last keyframe has too few corners to measure motion (a blank wall, a covered
  // lens, a dark stretch), the next keyframe is the first sharp frame that has corners of its
  // own (the scene came back into view) or, failing that, the first one at least this many
  // frames later, so that a featureless stretch yields a keyframe a second or so rather than
  // one per frame.
  int featureless_interval = 30;
  // At most this many keyframes (0 = no limit, the default: the motion and overlap criteria
  // above decide how many a video needs); beyond it they are subsampled evenly.
  int max_frames = 0;
  // Sharpness and motion are measured on frames downscaled to at most this size (speed; the
  // keyframes themselves are written at full resolution).
  int analysis_size = 640;
  int jpeg_quality = 95;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct KeyframeSummary {
  std::vector<std::string> names;  // keyframe files in the output folder, in video order
  size_t frames_read = 0;
  size_t frames_blurred = 0;
  // The frame count the container announces (0: unknown). Decoding that stops well short of it
  // (a truncated or damaged file) is warned about: the keyframes cover only what was read.
  size_t frames_announced = 0;
};

// Decoding stopped short of the frame count the container announces (0: unknown). Containers
// estimate the count for some formats, so only below 90 % of it.
inline bool DecodingStoppedShort(size_t frames_read, size_t frames_announced) {
  return frames_announced > 0 &&
         static_cast<double>(frames_read) < 0.9 * static_cast<double>(frames_announced);
}

// Throws varsfm::Error (one line naming `video`) when it is a folder or no file.
void CheckVideoFileExists(const std::filesystem::path& video);

// Decodes `video` and writes its keyframes as `output_dir`/frame_NNNNNN.jpg (NNNNNN = frame
// index in the video), creating the folder when the first keyframe is written. Deterministic:
// the same video and options give the same files. Throws varsfm::Error (one line naming the
// file) when the video does not exist, cannot be opened or has no decodable frame.
KeyframeSummary ExtractKeyframes(const std::filesystem::path& video,
                                 const std::filesystem::path& output_dir,
                                 const KeyframeOptions& options);

}  // namespace varsfm
