#include "varsfm/pipeline/evaluate.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "varsfm/eval/ground_truth.h"
#include "varsfm/io/colmap_model.h"
#include "varsfm/pipeline/render.h"
#include "varsfm/scene/holdout.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

namespace {

void WriteJson(const std::filesystem::path& path, const nlohmann::json& json) {
  WriteFileAtomically(path, [&](std::ostream& out) { out << json.dump(2) << '\n'; });
  info("wrote {}", path.string());
}

// The folder holding a model's other outputs (textured/, ...): OUT for OUT/sparse/0, for its
// parent OUT/sparse (ResolveColmapModelFolder) and for the single-model layout OUT/sparse.
std::filesystem::path OutputFolderOf(const std::filesystem::path& model_dir) {
  std::filesystem::path model =
      std::filesystem::absolute(ResolveColmapModelFolder(model_dir)).lexically_normal();
  if (model.filename().empty()) model = model.parent_path();  // a trailing slash
  const std::string name = model.filename().string();
  const bool numbered = !name.empty() && std::all_of(name.begin(), name.end(),
                                                     [](char c) { return c >= '0' && c <= '9'; });
  return numbered ? model.parent_path().parent_path() : model.parent_path();
}

}  // namespace

void EvaluateOptions::Check() const {
  evaluation.Check();
  CheckHoldout(holdout);
  if (gt_dir.empty() && !render)
    throw OptionError(
        "evaluate: give --gt (ground-truth cameras), --render (textured model), or both");
  if (render && image_dir.empty())
    throw OptionError("evaluate --render: --images (the photos) is required");
}

EvaluationReport RunEvaluation(const EvaluateOptions& options, OptionsCheck check) {
  if (check == OptionsCheck::kByStage) options.evaluation.Check();
  // Check both folders before reading either, so the message names the one that is wrong.
  if (!std::filesystem::is_directory(options.model_dir))
    Fail("{}: model folder does not exist", options.model_dir.string());
  if (!std::filesystem::is_directory(options.gt_dir))
    Fail("{}: ground-truth folder does not exist", options.gt_dir.string());
  const Reconstruction reconstruction = ReadColmapModel(options.model_dir);
  const GroundTruth ground_truth = ReadStrechaGroundTruth(options.gt_dir);
  EvaluationReport report =
      EvaluateAgainstGroundTruth(reconstruction, ground_truth, options.evaluation);
  // Images are paired with their ground truth by name: none paired is ground truth of another
  // scene (or named otherwise), not a model with no accuracy.
  if (report.num_model_images > 0 && report.num_registered == 0)
    Fail(
        "none of the {} registered images of {} has a camera in the ground truth {} (images are "
        "paired by name): ground truth of another scene?",
        report.num_model_images, options.model_dir.string(), options.gt_dir.string());
  if (!options.json_path.empty()) WriteJson(options.json_path, ToJson(report));
  return report;
}

std::string RunEvaluateCommand(const EvaluateOptions& options) {
  options.Check();
  std::string text;
  nlohmann::json json;
  if (!options.gt_dir.empty()) {
    EvaluateOptions gt = options;
    gt.json_path.clear();
    const EvaluationReport report = RunEvaluation(gt, OptionsCheck::kDoneByCaller);
    text += FormatReport(report);
    json = ToJson(report);
  }
  if (options.render) {
    RenderEvaluationOptions render;
    render.sparse = options.model_dir;
    render.textured = options.textured.empty() ? OutputFolderOf(options.model_dir) / "textured"
                                               : options.textured;
    render.image_dir = options.image_dir;
    render.render_dir = options.render_dir;
    render.holdout = options.holdout;
    const RenderEvaluationReport report = EvaluateRenders(render);
    text += FormatRenderReport(report);
    if (options.gt_dir.empty()) {
      json = ToJson(report);
    } else {
      json["render"] = ToJson(report);
    }
  }
  if (!options.json_path.empty()) WriteJson(options.json_path, json);
  return text;
}

}  // namespace varsfm
