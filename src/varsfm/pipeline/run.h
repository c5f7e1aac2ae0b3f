#pragma once
// `varsfm run INPUT OUT`: the whole chain with default options, photos or a video in, a
// textured model out: extract -> match -> map (sparse) -> densify (dense) -> mesh -> texture,
// stopping after the stage `until` names, then OUT/report.html of whatever was made.
// OUT/workspace.db is the workspace (re-running resumes).
#include <filesystem>
#include <string_view>

#include "varsfm/pipeline/densify.h"
#include "varsfm/pipeline/extract.h"
#include "varsfm/pipeline/map.h"
#include "varsfm/pipeline/match.h"
#include "varsfm/pipeline/mesh.h"
#include "varsfm/pipeline/render.h"
#include "varsfm/pipeline/report.h"
#include "varsfm/pipeline/texture.h"
#include "varsfm/util/enum_names.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

// The stages `run` can stop after, in order: the sparse model (map), the dense cloud (densify),
// the mesh, the texture (everything).
enum class RunStage { kSparse, kDense, kMesh, kTexture };

// The names `--until` takes.
inline constexpr EnumName<RunStage> kRunStageNames[] = {{RunStage::kSparse, "sparse"},
                                                        {RunStage::kDense, "dense"},
                                                        {RunStage::kMesh, "mesh"},
                                                        {RunStage::kTexture, "texture"}};

struct RunOptions {
  std::filesystem::path input;   // a folder of photos or a video file
  std::filesystem::path output;  // OUT
  // kAuto: sequential for video; else as MatchStrategy::kAuto says (retrieval for many images).
  MatchStrategy matching = MatchStrategy::kAuto;
  ExtractOptions extract;  // workspace / image_dir / video are filled in by RunAll
  MatchOptions match;      // workspace / strategy filled in
  // workspace / output / image_dir filled in. Its mapper's seed seeds every stage: RunAll
  // gives it to matching and multi-view stereo too (`run --seed`), so one number fixes the run.
  MapOptions map;
  RunStage until = RunStage::kTexture;  // the last stage run
  DenseReconstructionOptions dense;
  SurfaceOptions surface;
  PhotometricRefinementOptions refinement;  // of the surface, from the input's photos
  TextureMappingOptions texture;
  // Every N-th registered image by name is kept out of densify and texture, and the textured
  // model is scored on those views at the end (scene/holdout.h); 0: none.
  int holdout = 0;
  ReportOptions report;  // output filled in

  // Every stage's options, so that a bad value fails before the first stage starts. Throws
  // OptionError (util/option_check.h); the input and output are checked by RunAll.
  void Check() const;
};

struct RunSummary {
  MapSummary map;
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

// Throws varsfm::Error (one line) for a bad option, a missing input, a video that cannot be
// decoded, too few images or a scene that cannot be initialised: OUT is then removed if this run
// created it (a folder that existed is left as it was, but for OUT/workspace.db). Later stages
// throw as their commands do, and the sparse model and the outputs of the stages before stay in
// OUT.
RunSummary RunAll(const RunOptions& options, OptionsCheck check = OptionsCheck::kByStage);

}  // namespace varsfm
