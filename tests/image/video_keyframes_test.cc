#include "varsfm/image/video_keyframes.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "support/test_data.h"
#include "varsfm/image/image_file.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

constexpr int kFrames = 60;
constexpr int kStep = 8;  // pixels the view pans per frame
const std::set<int> kBlurred = {9, 10, 25, 40, 41, 42};

// A scene of random discs and rectangles, wide enough to pan a 320x240 view across it.
cv::Mat Texture() {
  cv::Mat texture(240, 320 + kStep * kFrames, CV_8UC3, cv::Scalar(128, 128, 128));
  cv::RNG rng(11);
  for (int i = 0; i < 400; ++i) {
    const cv::Point center(rng.uniform(0, texture.cols), rng.uniform(0, texture.rows));
    const cv::Scalar color(rng.uniform(0, 256), rng.uniform(0, 256), rng.uniform(0, 256));
    if (i % 2 == 0) {
      cv::circle(texture, center, rng.uniform(3, 20), color, cv::FILLED);
    } else {
      cv::rectangle(texture, center, center + cv::Point(rng.uniform(4, 30), rng.uniform(4, 30)),
                    color, cv::FILLED);
    }
  }
  return texture;
}

// A 320x240 MJPG video at 25 frames per second.
cv::VideoWriter OpenVideoWriter(const fs::path& path) {
  cv::VideoWriter writer(path.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 25,
                         cv::Size(320, 240));
  EXPECT_TRUE(writer.isOpened());
  return writer;
}

// An MJPG video panning across the texture, with strongly blurred frames at kBlurred.
fs::path WritePanVideo(const fs::path& path) {
  const cv::Mat texture = Texture();
  cv::VideoWriter writer = OpenVideoWriter(path);
  for (int i = 0; i < kFrames; ++i) {
    cv::Mat frame = texture(cv::Rect(i * kStep, 0, 320, 240)).clone();
    if (kBlurred.count(i)) cv::GaussianBlur(frame, frame, cv::Size(), 4.0);
    writer.write(frame);
  }
  return path;
}

int FrameIndex(const std::string& name) { return std::stoi(name.substr(6, 6)); }

TEST(VideoKeyframes, DropsBlurredFramesAndSpacesKeyframesByMotion) {
  testing::TempDir dir("video_keyframes");
  const fs::path video = WritePanVideo(dir.path() / "pan.avi");
  KeyframeOptions options;
  options.min_motion = 0.06;  // 0.06 * 400 px = 24 px: a keyframe every 3 frames of 8 px
  const KeyframeSummary summary = ExtractKeyframes(video, dir.path() / "frames", options);
  EXPECT_EQ(summary.frames_read, static_cast<size_t>(kFrames));
  EXPECT_EQ(summary.frames_blurred, kBlurred.size());
  ASSERT_GE(summary.names.size(), 10u);
  EXPECT_LE(summary.names.size(), 25u);
  int previous = -1;
  for (const std::string& name : summary.names) {
    const int index = FrameIndex(name);
    EXPECT_EQ(kBlurred.count(index), 0u) << "blurred frame kept: " << name;
    EXPECT_GT(index, previous);
    // Keyframes are at least the motion threshold apart (24 px = 3 frames).
    if (previous >= 0) EXPECT_GE(index - previous, 3) << name;
    previous = index;
    const cv::Mat written = ReadImagePixels(dir.path() / "frames" / name);
    EXPECT_EQ(written.size(), cv::Size(320, 240)) << name;
  }
  EXPECT_EQ(FrameIndex(summary.names.front()), 0);
}

TEST(VideoKeyframes, MaxFramesSubsamplesEvenlyAndRemovesTheRest) {
  testing::TempDir dir("video_keyframes_max");
  const fs::path video = WritePanVideo(dir.path() / "pan.avi");
  KeyframeOptions options;
  const KeyframeSummary all = ExtractKeyframes(video, dir.path() / "all", options);
  options.max_frames = 4;
  const KeyframeSummary capped = ExtractKeyframes(video, dir.path() / "capped", options);
  ASSERT_EQ(capped.names.size(), 4u);
  ASSERT_GT(all.names.size(), 4u);
  EXPECT_EQ(capped.names.front(), all.names.front());
  EXPECT_EQ(capped.names.back(), all.names.back());
  size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir.path() / "capped")) {
    ++files;
    EXPECT_NE(std::find(capped.names.begin(), capped.names.end(), entry.path().filename()),
              capped.names.end());
  }
  EXPECT_EQ(files, 4u);
}

// A flat grey stretch (no corners: motion cannot be measured) followed by the pan.
fs::path WriteBlankThenPanVideo(const fs::path& path, int blank_frames) {
  const cv::Mat texture = Texture();
  cv::VideoWriter writer = OpenVideoWriter(path);
  for (int i = 0; i < blank_frames; ++i)
    writer.write(cv::Mat(240, 320, CV_8UC3, cv::Scalar(128, 128, 128)));
  for (int i = 0; i < kFrames; ++i) writer.write(texture(cv::Rect(i * kStep, 0, 320, 240)).clone());
  return path;
}

TEST(VideoKeyframes, FeaturelessStretchGivesAKeyframePerIntervalAndContentEndsIt) {
  testing::TempDir dir("video_keyframes_blank");
  constexpr int kBlank = 50;
  const fs::path video = WriteBlankThenPanVideo(dir.path() / "blank.avi", kBlank);
  KeyframeOptions options;
  options.featureless_interval = 30;
  const KeyframeSummary summary = ExtractKeyframes(video, dir.path() / "frames", options);
  std::vector<int> indices;
  for (const std::string& name : summary.names) indices.push_back(FrameIndex(name));
  std::vector<int> blank;
  std::copy_if(indices.begin(), indices.end(), std::back_inserter(blank),
               [&](int i) { return i < kBlank; });
  // One keyframe per interval over the blank frames, not one per frame...
  EXPECT_EQ(blank, (std::vector<int>{0, 30}));
  // ...and the first frame with content becomes a keyframe at once.
  EXPECT_NE(std::find(indices.begin(), indices.end(), kBlank), indices.end());
}

TEST(VideoKeyframes, NoCapByDefault) {
  // Every frame moves far enough to be a keyframe; the default keeps all of them, more than
  // the 300 a fixed cap used to allow.
  testing::TempDir dir("video_keyframes_nocap");
  constexpr int kLongFrames = 320, kLongStep = 2;
  cv::Mat texture(240, 320 + kLongStep * kLongFrames, CV_8UC3, cv::Scalar(128, 128, 128));
  cv::RNG rng(5);
  for (int i = 0; i < 1500; ++i) {
    const cv::Point center(rng.uniform(0, texture.cols), rng.uniform(0, texture.rows));
    cv::circle(texture, center, rng.uniform(3, 12),
               cv::Scalar(rng.uniform(0, 256), rng.uniform(0, 256), rng.uniform(0, 256)),
               cv::FILLED);
  }
  const fs::path video = dir.path() / "long.avi";
  {
    cv::VideoWriter writer = OpenVideoWriter(video);
    for (int i = 0; i < kLongFrames; ++i)
      writer.write(texture(cv::Rect(i * kLongStep, 0, 320, 240)).clone());
  }
  KeyframeOptions options;
  options.min_motion = 0.001;  // 0.4 px: every frame's 2 px step is enough
  const KeyframeSummary summary = ExtractKeyframes(video, dir.path() / "frames", options);
  EXPECT_EQ(summary.frames_read, static_cast<size_t>(kLongFrames));
  EXPECT_GT(summary.names.size(), 300u);
}

// A video cut off half-way (a copy interrupted, a download stopped) decodes to its cut; the
// summary keeps the count the container announced, so that the shortfall is reported.
TEST(VideoKeyframes, ATruncatedVideoKeepsItsAnnouncedFrameCount) {
  testing::TempDir dir("video_keyframes_cut");
  const fs::path whole = WritePanVideo(dir.path() / "pan.avi");
  const KeyframeSummary full = ExtractKeyframes(whole, dir.path() / "whole", {});
  EXPECT_EQ(full.frames_read, static_cast<size_t>(kFrames));
  EXPECT_EQ(full.frames_announced, static_cast<size_t>(kFrames));

  const fs::path cut = testing::CopyFileHead(whole, dir.path() / "cut.avi", 0.5);
  const KeyframeSummary part = ExtractKeyframes(cut, dir.path() / "cut", {});
  EXPECT_GT(part.frames_read, 0u);
  EXPECT_LT(part.frames_read, static_cast<size_t>(0.6 * kFrames));
  EXPECT_EQ(part.frames_announced, static_cast<size_t>(kFrames));
}

TEST(VideoKeyframes, UnreadableVideoIsAnErrorAndWritesNothing) {
  testing::TempDir dir("video_keyframes_bad");
  EXPECT_THROW(ExtractKeyframes(dir.path() / "absent.avi", dir.path() / "frames", {}), Error);
  std::ofstream(dir.path() / "text.avi") << "not a video\n";
  try {
    ExtractKeyframes(dir.path() / "text.avi", dir.path() / "frames", {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("text.avi"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir.path() / "frames"));
}

// An MP4 keeps its index (the moov atom) at the end: cut short, it cannot be opened at all. The
// error says why, in one line, and FFmpeg prints nothing of its own beside it.
TEST(VideoKeyframes, AnMp4CutBeforeItsIndexIsAOneLineErrorWithFfmpegsReason) {
  testing::TempDir dir("video_keyframes_mp4");
  const fs::path whole = dir.path() / "pan.mp4";
  {
    cv::VideoWriter writer(whole.string(), cv::VideoWriter::fourcc('m', 'p', '4', 'v'), 25,
                           cv::Size(320, 240));
    ASSERT_TRUE(writer.isOpened());
    const cv::Mat texture = Texture();
    for (int i = 0; i < 10; ++i) writer.write(texture(cv::Rect(i * kStep, 0, 320, 240)).clone());
  }
  const fs::path cut = testing::CopyFileHead(whole, dir.path() / "cut.mp4", 0.5);
  ::testing::internal::CaptureStderr();
  std::string message;
  try {
    ExtractKeyframes(cut, dir.path() / "frames", {});
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(message, "cannot open video " + cut.string() + " (FFmpeg: moov atom not found)");
  EXPECT_FALSE(fs::exists(dir.path() / "frames"));
}

}  // namespace
}  // namespace varsfm
