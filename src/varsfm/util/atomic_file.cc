#include "varsfm/util/atomic_file.h"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <system_error>

#include <nlohmann/json.hpp>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

// A hidden sibling of `target` that no other writer uses: the process id keeps concurrent runs
// apart, the counter the threads of one run.
fs::path TemporarySibling(const fs::path& target) {
  static std::atomic<int> counter{0};
  // The target's extension is kept last: writers that pick the format by it (OpenCV's
  // encoders) write the temporary in the target's format.
  return target.parent_path() / fmt::format(".{}.tmp-{}-{}{}", target.filename().string(),
                                            ::getpid(), counter++, target.extension().string());
}

}  // namespace

void WriteFileViaTemporary(const fs::path& file,
                           const std::function<void(const fs::path&)>& write) {
  const fs::path tmp = TemporarySibling(file);
  std::error_code ec;
  try {
    write(tmp);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, file, ec);
  if (ec) {
    const std::string reason = ec.message();
    fs::remove(tmp, ec);
    Fail("{}: cannot write: {}", file.string(), reason);
  }
}

void WriteFileAtomically(const fs::path& file, const std::function<void(std::ostream&)>& write) {
  WriteFileViaTemporary(file, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) Fail("{}: cannot open for writing", file.string());
    write(out);
    out.close();
    if (!out) Fail("{}: write failed (disk full?)", file.string());
  });
}

void WriteBytesAtomically(const fs::path& file, const std::vector<uint8_t>& bytes) {
  WriteFileAtomically(file, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  });
}

void WriteJsonAtomically(const fs::path& file, const nlohmann::json& json) {
  WriteFileAtomically(file, [&](std::ostream& out) { out << json.dump(2) << "\n"; });
}

void WriteFilesAtomically(const fs::path& dir, const std::vector<std::string>& names,
                          const std::function<void(const fs::path&)>& write) {
  try {
    // A trailing slash gives an empty filename; normalise so the sibling name is right.
    fs::path target = fs::absolute(dir).lexically_normal();
    if (target.filename().empty()) target = target.parent_path();
    fs::create_directories(target.parent_path());
    const fs::path tmp = TemporarySibling(target);
    fs::remove_all(tmp);
    fs::create_directory(tmp);
    try {
      write(tmp);
      for (const auto& name : names)
        if (!fs::is_regular_file(tmp / name)) Fail("{}: was not written", (dir / name).string());
      if (!fs::exists(target)) {
        fs::rename(tmp, target);  // the whole folder appears at once
        return;
      }
      if (!fs::is_directory(target)) Fail("{}: exists and is not a folder", target.string());
      // An existing folder may hold other files (another model format, logs): replace only
      // ours, each by an atomic rename of a complete file.
      for (const auto& name : names) fs::rename(tmp / name, target / name);
      fs::remove_all(tmp);
    } catch (...) {
      std::error_code ec;
      fs::remove_all(tmp, ec);
      throw;
    }
  } catch (const fs::filesystem_error& e) {
    Fail("{}: cannot write: {}", dir.string(), e.code().message());
  }
}

}  // namespace varsfm
