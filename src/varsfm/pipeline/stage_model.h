#pragma once
// The sparse model the stages after `map` (densify, texture) work from, read the same way by
// each: its folder and the photos' folder must exist, and the held-out views (scene/holdout.h)
// are left out before the stage sees the model.
#include <filesystem>
#include <string_view>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// Reads the model in `sparse` (ReadColmapModel) and leaves out every `holdout`-th registered
// image (0: none), logging how many as `stage`. Throws varsfm::Error (one line) when `sparse`
// or `image_dir` is not a folder, for an unreadable model, and when fewer than `min_images`
// registered images are left (the message counts the held-out ones apart).
Reconstruction ReadStageModel(std::string_view stage, const std::filesystem::path& sparse,
                              const std::filesystem::path& image_dir, int holdout,
                              size_t min_images);

}  // namespace varsfm
