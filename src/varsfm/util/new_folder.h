#pragma once
// Creating a whole output folder so that it appears complete or not at all: the content is
// written into a hidden temporary sibling, which is renamed to the target only when the writer
// returns. An interrupted or failed export never leaves a half-written folder that a consumer
// (a splatting trainer, a NeRF loader) would read as a valid, smaller data set.
#include <filesystem>
#include <functional>

namespace varsfm {

// Creates `dir` and any missing parents (nothing when it exists as a folder). Throws
// varsfm::Error, one line naming `dir`, when it cannot: a stage's output folder under a path
// the user cannot write gets a clear error, not a raw filesystem exception.
void CreateFolder(const std::filesystem::path& dir);

// Calls `write` with the temporary folder, then renames it to `dir`. `dir` must not exist, or be
// an empty folder (it is then replaced). Throws varsfm::Error (one line naming `dir`) when `dir`
// holds anything, its parent cannot be written, or the rename fails; the temporary folder is
// removed on any failure, including an exception from `write`, which is rethrown.
void WriteNewFolder(const std::filesystem::path& dir,
                    const std::function<void(const std::filesystem::path&)>& write);

}  // namespace varsfm
