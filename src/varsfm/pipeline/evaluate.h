#pragma once
// `varsfm evaluate`: reads a COLMAP model (text or binary) and Strecha ground-truth cameras,
// and measures the model's accuracy (eval/evaluate.h), writing the report as JSON on request.
#include <filesystem>

#include "varsfm/eval/evaluate.h"

namespace varsfm {

struct EvaluateCommandOptions {
  std::filesystem::path model_dir;
  std::filesystem::path gt_dir;
  std::filesystem::path json_path;  // empty: no JSON
  EvaluationOptions evaluation;
};

// Throws varsfm::Error (one line) when a folder is missing or unreadable.
EvaluationReport RunEvaluation(const EvaluateCommandOptions& options);

}  // namespace varsfm
