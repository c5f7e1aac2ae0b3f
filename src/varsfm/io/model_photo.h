#pragma once
// A sparse model's photo read from disk for the stages that sample it (densify, texture,
// render): the file its image is named after, checked against its camera.
#include <filesystem>

#include <opencv2/core.hpp>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// Reads the photo of `image_id` from `image_dir` (BGR, EXIF orientation applied), checking that
// it exists and has its camera's size. Throws varsfm::Error naming the file.
cv::Mat ReadModelPhoto(const Reconstruction& reconstruction, image_t image_id,
                       const std::filesystem::path& image_dir);

}  // namespace varsfm
