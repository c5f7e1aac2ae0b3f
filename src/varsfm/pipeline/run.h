#pragma once
// `varsfm run INPUT OUT`: the whole chain with default options, photos or a video in, a sparse
// model out: extract -> match -> map. OUT/workspace.db is the workspace (re-running resumes).
#include <filesystem>
#include <string>

#include "varsfm/pipeline/extract.h"
#include "varsfm/pipeline/map.h"
#include "varsfm/pipeline/match.h"

namespace varsfm {

struct RunOptions {
  std::filesystem::path input;   // a folder of photos or a video file
  std::filesystem::path output;  // OUT
  // "auto": sequential for video and for more than 40 images, exhaustive otherwise.
  std::string matching = "auto";
  ExtractOptions extract;  // workspace / image_dir / video are filled in by RunAll
  MatchOptions match;      // workspace / strategy filled in
  MapOptions map;          // workspace / output / image_dir filled in
};

struct RunResult {
  MapResult map;
  double seconds_extract = 0;
  double seconds_match = 0;
  double seconds_map = 0;
};

// Throws varsfm::Error (one line) for a missing input, a video that cannot be decoded, too few
// images, or a scene that cannot be initialised.
RunResult RunAll(const RunOptions& options);

}  // namespace varsfm
