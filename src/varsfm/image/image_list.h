#pragma once
// Listing the photographs of an image folder.
#include <filesystem>
#include <string>
#include <vector>

namespace varsfm {

// True for the extensions varsfm reads (JPEG, PNG, HEIF, TIFF, BMP, ...), case-insensitive.
bool HasImageExtension(const std::filesystem::path& path);

// Whether a listing logs the files it skips (photos in formats varsfm does not read, videos,
// hidden files, links to a photo listed already, broken links): once per folder, by the stage
// that reads the photos; a later listing of the same folder (the report's) stays quiet.
enum class ListingNotes { kLogged, kQuiet };

// Every image file under `dir` (recursively), as '/'-separated names relative to `dir`, sorted
// by name so that image ids follow the names as in COLMAP. Files with other extensions are
// ignored, and so are hidden files and folders (names starting with '.'). Throws varsfm::Error
// when `dir` is not a readable folder.
std::vector<std::string> ListImages(const std::filesystem::path& dir,
                                    ListingNotes notes = ListingNotes::kLogged);

}  // namespace varsfm
