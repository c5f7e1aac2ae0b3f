#pragma once
// `varsfm evaluate`: reads a COLMAP model (text or binary) and Strecha ground-truth cameras,
// and measures the model's accuracy (eval/evaluate.h), writing the report as JSON on request.
// With --render it also (or, without --gt, only) scores the textured model by rendering it from
// every registered camera (pipeline/render.h).
#include <filesystem>
#include <string>

#include "varsfm/eval/evaluate.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

struct EvaluateOptions {
  std::filesystem::path model_dir;
  std::filesystem::path gt_dir;
  std::filesystem::path json_path;  // empty: no JSON
  EvaluationOptions evaluation;
  // --render: photometric comparison of the textured model with the photos.
  bool render = false;
  std::filesystem::path textured;   // OBJ or its folder; empty: OUT/textured (model OUT/sparse[/0])
  std::filesystem::path image_dir;  // the photos (required with render)
  std::filesystem::path render_dir;  // optional: where to write the renderings
  int holdout = 0;                   // the held-out views reported apart (pipeline/render.h)

  // Throws OptionError (util/option_check.h) for a bad value, neither --gt nor --render, or
  // --render without --images; files are checked when the stage runs.
  void Check() const;
};

// The ground-truth evaluation. Throws varsfm::Error (one line) when a folder is missing or
// unreadable. `check`: kDoneByCaller when options.evaluation was checked already.
EvaluationReport RunEvaluation(const EvaluateOptions& options,
                               OptionsCheck check = OptionsCheck::kByStage);

// The whole `evaluate` command: ground truth when gt_dir is set, renderings when render is set
// (at least one). Returns the readable report. The JSON holds the ground-truth report at the top
// level (as without --render) with the rendering report under "render", or only the rendering
// report when there is no ground truth. Throws varsfm::Error (one line).
std::string RunEvaluateCommand(const EvaluateOptions& options);

}  // namespace varsfm
