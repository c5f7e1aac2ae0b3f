#pragma once
// The sparse model the stages after `map` (densify, mesh's refinement, texture) work from, read
// the same way by each: its folder and the photos' folder must exist, the held-out views
// (scene/holdout.h) are left out before the stage sees the model, and every photo the stage will
// read must be there -- looked for before the stage's work, so that a wrong --images fails at
// once rather than after minutes of multi-view stereo or surface reconstruction.
#include <filesystem>
#include <string_view>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// Reads the model in `sparse` (ReadColmapModel) and leaves out every `holdout`-th registered
// image (0: none), logging how many as `stage`. Throws varsfm::Error (one line) when `sparse`
// or `image_dir` is not a folder, for an unreadable model, when fewer than `min_images`
// registered images are left (the message counts the held-out ones apart), and when a registered
// image's photo is not a file in `image_dir` (the message counts them and names the first).
Reconstruction ReadStageModel(std::string_view stage, const std::filesystem::path& sparse,
                              const std::filesystem::path& image_dir, int holdout,
                              size_t min_images);

}  // namespace varsfm
