#include "varsfm/image/opencv_io_plugin.h"

#include <dlfcn.h>

#include <filesystem>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

struct LoadResult {
  OpenCvIoPlugin plugin;
  bool loaded = false;
  std::string error;
};

std::vector<fs::path> Candidates() {
  std::vector<fs::path> candidates;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path() / kOpenCvIoPluginFile);
#ifdef VARSFM_OPENCV_IO_PLUGIN_PATH
  // Set by CMake to the plug-in's absolute path in the build tree.
  const fs::path built = VARSFM_OPENCV_IO_PLUGIN_PATH;
  if (candidates.empty() || built != candidates.front()) candidates.push_back(built);
#endif
  return candidates;
}

// Resolves every entry point of `handle` into *plugin; false (with *error) if one is missing
// or the plug-in was built for another interface version.
bool Resolve(void* handle, OpenCvIoPlugin* plugin, std::string* error) {
  auto symbol = [&](const char* name) {
    void* address = dlsym(handle, name);
    if (address == nullptr) *error = fmt::format("no symbol {}", name);
    return address;
  };
  const auto version = reinterpret_cast<decltype(&varsfm_opencv_io_abi_version)>(
      symbol("varsfm_opencv_io_abi_version"));
  if (version == nullptr) return false;
  if (version() != VARSFM_OPENCV_IO_ABI_VERSION) {
    *error =
        fmt::format("interface version {}, expected {}", version(), VARSFM_OPENCV_IO_ABI_VERSION);
    return false;
  }
  plugin->decode = reinterpret_cast<decltype(plugin->decode)>(symbol("varsfm_opencv_io_decode"));
  plugin->write = reinterpret_cast<decltype(plugin->write)>(symbol("varsfm_opencv_io_write"));
  plugin->video_open =
      reinterpret_cast<decltype(plugin->video_open)>(symbol("varsfm_opencv_io_video_open"));
  plugin->video_read =
      reinterpret_cast<decltype(plugin->video_read)>(symbol("varsfm_opencv_io_video_read"));
  plugin->video_get =
      reinterpret_cast<decltype(plugin->video_get)>(symbol("varsfm_opencv_io_video_get"));
  plugin->video_close =
      reinterpret_cast<decltype(plugin->video_close)>(symbol("varsfm_opencv_io_video_close"));
  return plugin->decode && plugin->write && plugin->video_open && plugin->video_read &&
         plugin->video_get && plugin->video_close;
}

LoadResult Load() {
  LoadResult result;
  std::vector<std::string> failures;
  for (const fs::path& candidate : Candidates()) {
    std::error_code ec;
    if (!fs::exists(candidate, ec)) {
      failures.push_back(fmt::format("{} (absent)", candidate.string()));
      continue;
    }
    void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* message = dlerror();
      failures.push_back(fmt::format("{} ({})", candidate.string(), message ? message : "?"));
      continue;
    }
    std::string error;
    if (Resolve(handle, &result.plugin, &error)) {
      result.loaded = true;
      return result;
    }
    dlclose(handle);
    failures.push_back(fmt::format("{} ({})", candidate.string(), error));
  }
  result.error =
      failures.empty() ? "no location to look in" : fmt::format("{}", fmt::join(failures, "; "));
  return result;
}

}  // namespace

const OpenCvIoPlugin* LoadOpenCvIoPlugin(std::string* why) {
  // The one piece of process-wide state: loading costs ~0.2 s (OpenCV's imgcodecs/videoio and
  // their ~210 libraries), so it happens once, on first use, and the handle is never closed
  // (OpenCV's libraries keep threads and static state). A function-local static gives that
  // without a global constructor, and C++ makes its initialisation thread-safe.
  static const LoadResult result = Load();
  if (!result.loaded) {
    if (why != nullptr) *why = result.error;
    return nullptr;
  }
  return &result.plugin;
}

const OpenCvIoPlugin& RequireOpenCvIoPlugin(const std::string& failure, const std::string& needs) {
  std::string why;
  const OpenCvIoPlugin* plugin = LoadOpenCvIoPlugin(&why);
  if (plugin == nullptr)
    Fail("{}: {} the OpenCV I/O plug-in ({}), not found: {}", failure, needs, kOpenCvIoPluginFile,
         why);
  return *plugin;
}

}  // namespace varsfm
