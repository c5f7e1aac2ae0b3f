#include "fuzz_support.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>

namespace varsfm::fuzz {
namespace fs = std::filesystem;

namespace {

fs::path MakeScratchDir() {
  spdlog::set_level(spdlog::level::off);
  // The pid keeps parallel fuzzing jobs (-jobs, -fork) apart.
  const fs::path dir = fs::temp_directory_path() / ("varsfm-fuzz-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

}  // namespace

const fs::path& ScratchDir() {
  static const fs::path dir = MakeScratchDir();
  static const bool registered = [] {
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(ScratchDir(), ec);
    });
    return true;
  }();
  (void)registered;
  return dir;
}

void WriteBytes(const fs::path& path, const void* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out.flush()) std::abort();  // a harness that cannot write its input tests nothing
}

std::vector<std::string> SplitParts(const uint8_t* data, size_t size, size_t count) {
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> parts;
  size_t start = 0;
  while (parts.size() + 1 < count) {
    const size_t at = all.find(kPartSeparator, start);
    if (at == std::string_view::npos) break;
    parts.emplace_back(all.substr(start, at - start));
    start = at + kPartSeparator.size();
  }
  parts.emplace_back(all.substr(std::min(start, all.size())));
  parts.resize(count);
  return parts;
}

std::string JoinParts(const std::vector<std::string>& parts) {
  std::string joined;
  for (size_t i = 0; i < parts.size(); ++i) {
    if (i > 0) joined += kPartSeparator;
    joined += parts[i];
  }
  return joined;
}

std::filesystem::path WriteParts(const uint8_t* data, size_t size, const std::string& folder,
                                 const std::vector<std::string>& names) {
  const std::filesystem::path dir = ScratchDir() / folder;
  std::filesystem::create_directories(dir);
  const std::vector<std::string> parts = SplitParts(data, size, names.size());
  for (size_t i = 0; i < names.size(); ++i)
    WriteBytes(dir / names[i], parts[i].data(), parts[i].size());
  return dir;
}

}  // namespace varsfm::fuzz
