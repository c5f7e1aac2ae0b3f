#pragma once
// The images an export writes: every registered image, each with its photo on disk. Checked
// before anything is written, so a missing photo fails the export with nothing left behind.
#include <filesystem>
#include <string>
#include <vector>

#include "varsfm/scene/reconstruction.h"

namespace varsfm {

// The registered image ids, in id order. Throws varsfm::Error (one line) when there is none or
// a photo is missing from `image_dir`.
std::vector<image_t> ExportedImageIds(const Reconstruction& reconstruction,
                                      const std::filesystem::path& image_dir);

// The name a photo is exported under: its own, or, for a format the trainers' loaders do not
// read without plug-ins (HEIF: HEIC, the iPhone's, and AVIF; camera raw files; PIL and OpenCV
// open none), its name with ".jpg" appended (IMG_0001.HEIC.jpg: no clash with an IMG_0001.jpg
// beside it). Such a photo is re-encoded as JPEG, developed.
std::string ExportedPhotoName(const std::string& name);

}  // namespace varsfm
