#include "varsfm/pipeline/evaluate.h"

#include <fstream>

#include <nlohmann/json.hpp>

#include "varsfm/eval/ground_truth.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

namespace varsfm {

EvaluationReport RunEvaluation(const EvaluateCommandOptions& options) {
  // Check both folders before reading either, so the message names the one that is wrong.
  if (!std::filesystem::is_directory(options.model_dir))
    Fail("{}: model folder does not exist", options.model_dir.string());
  if (!std::filesystem::is_directory(options.gt_dir))
    Fail("{}: ground-truth folder does not exist", options.gt_dir.string());
  const Reconstruction reconstruction = ReadColmapModel(options.model_dir);
  const GroundTruth ground_truth = ReadStrechaGroundTruth(options.gt_dir);
  EvaluationReport report =
      EvaluateAgainstGroundTruth(reconstruction, ground_truth, options.evaluation);
  if (!options.json_path.empty()) {
    const auto tmp = options.json_path.string() + ".tmp";
    {
      std::ofstream out(tmp);
      out << ToJson(report).dump(2) << '\n';
      if (!out) Fail("{}: cannot write", options.json_path.string());
    }
    std::error_code ec;
    std::filesystem::rename(tmp, options.json_path, ec);
    if (ec) Fail("{}: cannot write: {}", options.json_path.string(), ec.message());
    info("wrote {}", options.json_path.string());
  }
  return report;
}

}  // namespace varsfm
