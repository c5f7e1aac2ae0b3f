#pragma once
// `varsfm demo`: the built-in demonstration that works on any fresh clone. It renders a
// synthetic textured scene filmed by a zooming camera (synthetic/rendered_scene.h), runs the
// whole chain on the images, and measures the model against the scene's exact ground truth.
#include <filesystem>

#include "varsfm/eval/evaluate.h"
#include "varsfm/pipeline/run.h"
#include "varsfm/synthetic/rendered_scene.h"

namespace varsfm {

struct DemoOptions {
  std::filesystem::path output;  // OUT/images, OUT/gt, then the run's outputs in OUT
  RenderedSceneOptions scene;
  RunOptions run;  // input/output filled in

  // Throws OptionError (util/option_check.h) for a bad value.
  void Check() const;
};

struct DemoSummary {
  RunSummary run;
  EvaluationReport evaluation;
};

DemoSummary RunDemo(const DemoOptions& options);

}  // namespace varsfm
