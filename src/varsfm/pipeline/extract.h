#pragma once
// Stage 1 of the pipeline: photographs or a video in, one camera + image + SIFT features per
// image in the workspace database. Incremental: images already holding keypoints are skipped.
#include <cstddef>
#include <filesystem>

#include "varsfm/feature/sift.h"
#include "varsfm/image/video_keyframes.h"
#include "varsfm/pipeline/video_frames.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

struct ExtractOptions {
  std::filesystem::path workspace;
  // Exactly one of the two: a folder of images, or a video whose keyframes are written to its
  // folder under VideoFramesDir(workspace) (pipeline/video_frames.h) and extracted from there.
  std::filesystem::path image_dir;
  std::filesystem::path video;
  SiftOptions sift;
  KeyframeOptions keyframes;
  int min_image_size = 32;  // smaller images (either side, pixels) are skipped with a warning
  int min_features = 16;    // fewer features: a warning (the image is kept, it may not register)
  int threads = 0;          // 0: all cores
  // The SIFT scale spaces in memory at once (SiftMemoryBytes, feature/sift.h) stay within this
  // many MB: fewer photos are extracted at once where one per thread would exceed it, and a
  // photo whose scale space does not fit beside the others' waits (0: half the machine's memory,
  // or of the container's limit where lower). The features do not depend on it.
  size_t memory_mb = 0;

  // Throws OptionError (util/option_check.h) for a bad value; files are checked when the stage
  // runs.
  void Check() const;
};

struct ExtractSummary {
  std::filesystem::path image_dir;  // the folder image names are relative to
  size_t num_images = 0;            // listed (or video keyframes)
  size_t num_existing = 0;          // already extracted in the workspace, skipped
  size_t num_extracted = 0;         // written by this run
  size_t num_unusable = 0;          // unreadable or too small, skipped with a warning
  size_t num_features = 0;          // total over the images written by this run
  size_t video_frames = 0;          // frames decoded (video input)
  size_t video_blurred = 0;         // of which dropped as blurred
  size_t video_announced = 0;       // frames the container announces (0: unknown)
  double seconds = 0;
};

// Runs the extraction. Inputs are validated before the workspace is opened: a missing path, an
// empty folder or no readable image throws varsfm::Error and leaves the workspace file as it was
// (not created if absent). Every image is written in one transaction (camera, image,
// keypoints, descriptors) in name order, so image ids follow the names and an interrupted run
// leaves only whole images. Each image gets its own SIMPLE_RADIAL camera as COLMAP's extractor
// writes it: f = EXIF focal (pixels) if known, else 1.2 max(w, h); principal point at the centre.
ExtractSummary RunExtraction(const ExtractOptions& options,
                             OptionsCheck check = OptionsCheck::kByStage);

}  // namespace varsfm
