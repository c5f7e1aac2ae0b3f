#pragma once
// A file's identity without reading all of it: its size and an FNV-1a hash of its first and last
// 64 KiB. The same file gives the same text wherever it lies; another one (a photo resized or
// re-encoded under the same name, another video) almost surely not.
#include <filesystem>
#include <string>

namespace varsfm {

// Throws varsfm::Error (one line naming the file) when it cannot be read.
std::string FileFingerprint(const std::filesystem::path& file);

}  // namespace varsfm
