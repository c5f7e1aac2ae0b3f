#include "varsfm/util/new_folder.h"

#include <unistd.h>

#include <system_error>

#include "varsfm/util/error.h"

namespace varsfm {

void CreateFolder(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) Fail("{}: cannot create ({})", dir.string(), ec.message());
  if (!fs::is_directory(dir, ec)) Fail("{} exists and is not a folder", dir.string());
}

void WriteNewFolder(const std::filesystem::path& dir,
                    const std::function<void(const std::filesystem::path&)>& write) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) Fail("{} exists and is not a folder", dir.string());
    if (!fs::is_empty(dir, ec)) {
      Fail("{} already holds files; give a new or empty folder", dir.string());
    }
  }
  const fs::path parent = fs::absolute(dir).parent_path();
  CreateFolder(parent);
  const fs::path tmp =
      parent / fmt::format(".{}.partial-{}", fs::absolute(dir).filename().string(), ::getpid());
  fs::remove_all(tmp, ec);
  fs::create_directory(tmp, ec);
  if (ec) Fail("{}: cannot create ({})", tmp.string(), ec.message());
  try {
    write(tmp);
    if (fs::exists(dir)) fs::remove(dir);  // empty, checked above
    fs::rename(tmp, dir);
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(tmp, ec);
    Fail("{}: cannot write ({})", dir.string(), e.code().message());
  } catch (...) {
    fs::remove_all(tmp, ec);
    throw;
  }
}

}  // namespace varsfm
