#include "varsfm/pipeline/video_frames.h"

#include <array>
#include <cstdint>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/file_fingerprint.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

constexpr const char* kIdentityFile = "video.txt";

std::string ReadIdentity(const fs::path& folder) {
  std::ifstream file(folder / kIdentityFile);
  std::string line;
  std::getline(file, line);
  return line;
}

}  // namespace

fs::path VideoFramesDir(const fs::path& workspace) {
  return workspace.parent_path() / (workspace.stem().string() + "_frames");
}

std::string VideoFramesFolderName(const fs::path& workspace, const fs::path& video) {
  CheckVideoFileExists(video);
  std::error_code ec;
  const fs::path frames = VideoFramesDir(workspace);
  const std::string identity = FileFingerprint(video);
  const std::string stem = video.stem().string();
  std::string name = stem;
  for (int k = 2; fs::exists(frames / name, ec) && ReadIdentity(frames / name) != identity; ++k) {
    name = fmt::format("{}_{}", stem, k);
  }
  return name;
}

KeyframeSummary ExtractVideoFrames(const fs::path& workspace, const fs::path& video,
                                   const KeyframeOptions& options) {
  std::error_code ec;
  const fs::path frames = VideoFramesDir(workspace);
  const std::string name = VideoFramesFolderName(workspace, video);
  const std::string identity = FileFingerprint(video);
  const fs::path folder = frames / name;
  const bool created = !fs::exists(folder, ec);
  KeyframeSummary summary;
  try {
    fs::create_directories(folder, ec);
    if (ec) Fail("cannot create folder {}: {}", folder.string(), ec.message());
    if (created) {
      WriteFileAtomically(folder / kIdentityFile, [&](std::ostream& out) {
        out << identity << "\n" << fs::absolute(video).string() << "\n";
      });
    }
    summary = ExtractKeyframes(video, folder, options);
  } catch (...) {
    if (created) fs::remove_all(folder, ec);
    if (fs::is_empty(frames, ec)) fs::remove(frames, ec);
    throw;
  }
  for (std::string& keyframe : summary.names) keyframe = name + "/" + keyframe;
  return summary;
}

}  // namespace varsfm
