#pragma once
// The images an export writes: every registered image, each with its photo on disk. Checked
// before anything is written, so a missing photo fails the export with nothing left behind.
#include <filesystem>
#include <vector>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// The registered image ids, in id order. Throws varsfm::Error (one line) when there is none or
// a photo is missing from `image_dir`.
std::vector<image_t> ExportedImageIds(const Reconstruction& reconstruction,
                                      const std::filesystem::path& image_dir);

}  // namespace varsfm
