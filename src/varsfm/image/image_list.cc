#include "varsfm/image/image_list.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <system_error>

#include "varsfm/util/error.h"

namespace varsfm {

bool HasImageExtension(const std::filesystem::path& path) {
  static constexpr std::array<const char*, 7> kExtensions = {".jpg",  ".jpeg", ".png", ".tif",
                                                             ".tiff", ".bmp",  ".jpe"};
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

std::vector<std::string> ListImages(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(dir, ec)) Fail("image folder {} does not exist", dir.string());
  if (!fs::is_directory(dir, ec)) Fail("{} is not a folder", dir.string());

  std::vector<std::string> names;
  fs::recursive_directory_iterator it(dir, fs::directory_options::follow_directory_symlink, ec);
  if (ec) Fail("cannot list image folder {}: {}", dir.string(), ec.message());
  for (; it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) Fail("cannot list image folder {}: {}", dir.string(), ec.message());
    if (!it->is_regular_file(ec) || !HasImageExtension(it->path())) continue;
    // generic_string() gives '/' separators on every platform, as COLMAP stores names.
    names.push_back(fs::relative(it->path(), dir, ec).generic_string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace varsfm
