#pragma once
// `varsfm run INPUT OUT`: the whole chain with default options, photos or a video in, a
// textured model out: extract -> match -> map (sparse) -> densify (dense) -> mesh -> texture,
// stopping after the stage `until` names, then OUT/report.html of whatever was made.
// OUT/workspace.db is the workspace (re-running resumes).
#include <filesystem>
#include <string>

#include "varsfm/pipeline/densify.h"
#include "varsfm/pipeline/extract.h"
#include "varsfm/pipeline/map.h"
#include "varsfm/pipeline/match.h"
#include "varsfm/pipeline/mesh.h"
#include "varsfm/pipeline/render.h"
#include "varsfm/pipeline/report.h"
#include "varsfm/pipeline/texture.h"

namespace varsfm {

struct RunOptions {
  std::filesystem::path input;   // a folder of photos or a video file
  std::filesystem::path output;  // OUT
  // "auto": sequential for video and for more than 40 images, exhaustive otherwise.
  std::string matching = "auto";
  ExtractOptions extract;  // workspace / image_dir / video are filled in by RunAll
  MatchOptions match;      // workspace / strategy filled in
  MapOptions map;          // workspace / output / image_dir filled in
  // The last stage run: "sparse" (map), "dense" (densify), "mesh" or "texture" (everything).
  std::string until = "texture";
  DensifyOptions dense;
  SurfaceOptions surface;
  TextureOptions texture;
  // Every N-th registered image by name is kept out of densify and texture, and the textured
  // model is scored on those views at the end (scene/holdout.h); 0: none.
  int holdout = 0;
  ReportOptions report;  // output filled in
};

struct RunResult {
  MapResult map;
  double seconds_extract = 0;
  double seconds_match = 0;
  double seconds_map = 0;
  double seconds_densify = 0;  // 0 for stages not run
  double seconds_mesh = 0;
  double seconds_texture = 0;
  // With a holdout: the textured model rendered from every registered camera, held-out views
  // apart (held_out.num_images == 0 otherwise).
  RenderEvaluationReport renders;
  std::filesystem::path report;  // OUT/report.html
};

// Throws varsfm::Error (one line) for a missing input, a video that cannot be decoded, too few
// images, a scene that cannot be initialised, or an unknown `until`; later stages throw as their
// commands do (the outputs of the stages before stay in OUT).
RunResult RunAll(const RunOptions& options);

}  // namespace varsfm
