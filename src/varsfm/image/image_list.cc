#include "varsfm/image/image_list.h"

#include <algorithm>
#include <array>
#include <map>
#include <system_error>

#include "varsfm/image/heif_codec.h"
#include "varsfm/image/image_file.h"
#include "varsfm/image/raw_codec.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

// True when `ancestor` is `path` or one of its parent folders (both canonical).
bool IsWithin(const fs::path& path, const fs::path& ancestor) {
  const auto [end, unused] =
      std::mismatch(ancestor.begin(), ancestor.end(), path.begin(), path.end());
  return end == ancestor.end();
}

// What a listing says about the files it skips: logged (a stage reading the photos), or not (a
// second listing of the same folder, whose lines the user has seen).
struct SkipNotes {
  ListingNotes mode;
  template <typename... Args>
  void Warn(fmt::format_string<Args...> format, Args&&... args) const {
    if (mode == ListingNotes::kLogged) warn(format, std::forward<Args>(args)...);
  }
  template <typename... Args>
  void Info(fmt::format_string<Args...> format, Args&&... args) const {
    if (mode == ListingNotes::kLogged) info(format, std::forward<Args>(args)...);
  }
};

// An image file found while listing: its name in the folder and the file it is (links resolved).
struct FoundImage {
  std::string name;
  fs::path file;
};

// Keeps one name per file: several names for one file (a link to a photo of the set, a folder
// linked twice) are one photo, and extracting it twice would give two images of one view with
// identical features. The name that is not a link wins, else the first by name.
std::vector<std::string> OneNamePerFile(std::vector<FoundImage> found, const fs::path& root,
                                        const SkipNotes& notes) {
  std::sort(found.begin(), found.end(),
            [](const FoundImage& a, const FoundImage& b) { return a.name < b.name; });
  std::map<fs::path, const FoundImage*> kept;
  for (const FoundImage& image : found) {
    const auto [it, inserted] = kept.emplace(image.file, &image);
    if (!inserted && root / image.name == image.file) it->second = &image;
  }
  std::vector<std::string> names;
  for (const FoundImage& image : found) {
    const FoundImage* chosen = kept.at(image.file);
    if (chosen == &image) {
      names.push_back(image.name);
    } else {
      notes.Warn("skipping {}: a link to {}, the same photo", image.name, chosen->name);
    }
  }
  return names;
}

// Picture formats that varsfm does not decode (GIF, 1-bit PBM): skipped like any other file, but
// named in a warning, since a user who gave them meant them as photos.
bool IsUnreadablePhotoFormat(const fs::path& path) {
  static constexpr std::array<const char*, 2> kExtensions = {".gif", ".pbm"};
  const std::string ext = LowerCaseExtension(path);
  return std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

// Videos, which a phone's camera roll holds among its photos: read on their own (`run VIDEO`,
// `extract --video`), so skipped here but named, rather than dropped in silence.
bool IsVideoFile(const fs::path& path) {
  static constexpr std::array<const char*, 12> kExtensions = {".mov", ".mp4",  ".m4v", ".avi",
                                                              ".mkv", ".webm", ".mts", ".m2ts",
                                                              ".3gp", ".wmv",  ".mpg", ".mpeg"};
  const std::string ext = LowerCaseExtension(path);
  return std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

}  // namespace

bool HasImageExtension(const fs::path& path) {
  // JPEG, PNG, HEIF (HEIC, AVIF) and camera raw files are decoded directly, the others by
  // OpenCV's image codecs through the I/O plug-in (image_file.h).
  static constexpr std::array<const char*, 13> kExtensions = {
      ".jpg",  ".jpeg", ".jpe", ".png", ".tif", ".tiff", ".bmp",
      ".webp", ".jp2",  ".j2k", ".pnm", ".ppm", ".pgm"};
  const std::string ext = LowerCaseExtension(path);
  return IsHeifPhotoName(path) || IsRawPhotoName(path) ||
         std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

std::vector<std::string> ListImages(const fs::path& dir, ListingNotes mode) {
  const SkipNotes notes{mode};
  std::error_code ec;
  if (!fs::exists(dir, ec)) Fail("image folder {} does not exist", dir.string());
  if (!fs::is_directory(dir, ec)) Fail("{} is not a folder", dir.string());
  const fs::path root = fs::canonical(dir, ec);
  if (ec) Fail("cannot list image folder {}: {}", dir.string(), ec.message());

  std::vector<FoundImage> found;
  std::vector<std::string> unreadable;  // photos in formats varsfm does not read
  std::vector<std::string> videos;
  std::vector<std::string> hidden;  // hidden folders and hidden image files, for one line
  fs::recursive_directory_iterator it(dir, fs::directory_options::follow_directory_symlink, ec);
  if (ec) Fail("cannot list image folder {}: {}", dir.string(), ec.message());
  for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) Fail("cannot list image folder {}: {}", dir.string(), ec.message());
    // Names as found, links not resolved (fs::relative would resolve them, turning a link into
    // its target's name); generic_string() gives '/' separators, as COLMAP stores names.
    const std::string name = it->path().lexically_relative(dir).generic_string();
    std::error_code status_ec;
    // Hidden names are not the user's photos: macOS's "._IMG_0001.jpg" metadata beside each
    // copied photo, a file manager's .thumbnails/ of small copies, a .git/ folder.
    if (it->path().filename().string().starts_with('.')) {
      if (it->is_directory(status_ec)) {
        it.disable_recursion_pending();
        hidden.push_back(name + "/");
      } else if (HasImageExtension(it->path())) {
        hidden.push_back(name);
      }
      continue;
    }
    if (it->is_directory(status_ec)) {
      // A linked folder that contains the link (e.g. `sub -> .`) would be listed again and
      // again down to the system's depth limit.
      const fs::path folder = fs::canonical(it->path(), status_ec);
      std::error_code parent_ec;
      const fs::path parent = fs::canonical(it->path().parent_path(), parent_ec);
      if (!status_ec && !parent_ec && IsWithin(parent, folder)) {
        notes.Warn("skipping {}/: a link to folder {} that contains it (a loop)", name,
                   folder.string());
        it.disable_recursion_pending();
      }
      continue;
    }
    if (!HasImageExtension(it->path())) {
      if (IsUnreadablePhotoFormat(it->path())) unreadable.push_back(name);
      if (IsVideoFile(it->path())) videos.push_back(name);
      continue;
    }
    const bool is_file = it->is_regular_file(status_ec);
    if (status_ec) {
      const bool loop = status_ec == std::errc::too_many_symbolic_link_levels;
      notes.Warn("skipping {}: {}", name, loop ? "a link loop" : "a link to a missing file");
      continue;
    }
    if (!is_file) continue;
    fs::path file = fs::canonical(it->path(), status_ec);
    if (status_ec) {
      notes.Warn("skipping {}: {}", name, status_ec.message());
      continue;
    }
    found.push_back({name, std::move(file)});
  }
  if (!hidden.empty())
    notes.Info("skipping {} hidden file(s) or folder(s) (names starting with '.', e.g. {})",
               hidden.size(), hidden.front());
  if (!unreadable.empty())
    notes.Warn(
        "skipping {} photo(s) in a format varsfm does not read (e.g. {}): convert them to JPEG or "
        "PNG",
        unreadable.size(), unreadable.front());
  if (!videos.empty())
    notes.Warn(
        "skipping {} video(s) among the photos (e.g. {}): a video is read on its own "
        "(varsfm run VIDEO OUT)",
        videos.size(), videos.front());
  return OneNamePerFile(std::move(found), root, notes);
}

}  // namespace varsfm
