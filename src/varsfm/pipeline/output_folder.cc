#include "varsfm/pipeline/output_folder.h"

#include <algorithm>
#include <system_error>
#include <vector>

#include "varsfm/util/error.h"

namespace varsfm {

namespace {

// Whether `output` holds what `run` writes first, or what `map` writes first and last (a run
// stopped between them still counts).
bool HoldsVarsfmMarks(const std::filesystem::path& output) {
  std::error_code ec;
  for (const char* mark : {"workspace.db", "sparse", "summary.json"})
    if (std::filesystem::exists(output / mark, ec)) return true;
  return false;
}

// What each stage after `map` writes into the output folder: the one list of the chain's outputs.
struct StageOutputs {
  ChainStage stage;
  std::vector<const char*> names;
};
const StageOutputs kStageOutputs[] = {
    {ChainStage::kDensify, {"dense.ply", "dense.ply.vis", "dense_summary.json"}},
    {ChainStage::kMesh, {"mesh.ply"}},
    {ChainStage::kTexture, {"model.glb", "textured"}},
    {ChainStage::kReport, {"report.html"}}};

}  // namespace

void CheckOutputFolderIsOurs(const std::filesystem::path& output) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(output, ec) || fs::is_empty(output, ec) || HoldsVarsfmMarks(output)) return;
  Fail(
      "output folder {} holds other files and no workspace.db, sparse/ or summary.json of "
      "varsfm's: give a new or empty folder (varsfm replaces its earlier results in a folder it "
      "wrote)",
      output.string());
}

void CheckOutputOutsideImages(const std::filesystem::path& output,
                              const std::filesystem::path& image_dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  // A folder that cannot be made (a file stands in its path) gets that error where it is made.
  fs::path existing = fs::absolute(output, ec);
  while (!existing.empty() && !fs::exists(existing, ec) && existing != existing.parent_path())
    existing = existing.parent_path();
  if (!fs::is_directory(existing, ec)) return;
  // Absolute, links resolved, without a trailing separator (which would iterate as an empty last
  // component).
  const auto normal = [&](const fs::path& path) {
    const fs::path p = fs::weakly_canonical(path, ec);
    return p.has_filename() ? p : p.parent_path();
  };
  const fs::path images = normal(image_dir), out = normal(output);
  if (ec) return;
  // Component by component: "photos2" is not inside "photos".
  const auto [image_end, out_it] =
      std::mismatch(images.begin(), images.end(), out.begin(), out.end());
  if (image_end != images.end()) return;
  Fail(
      "output folder {} is the image folder {} or inside it: its files would be read as photos; "
      "give a folder outside it",
      output.string(), image_dir.string());
}

void RemoveOutputsAfter(const std::filesystem::path& output, ChainStage stage) {
  if (!HoldsVarsfmMarks(output)) return;
  std::error_code ec;
  for (const StageOutputs& outputs : kStageOutputs)
    if (outputs.stage > stage)
      for (const char* name : outputs.names) std::filesystem::remove_all(output / name, ec);
}

void WriteOutputsTogether(const std::filesystem::path& output, ChainStage stage,
                          const std::function<void()>& write) {
  try {
    write();
  } catch (...) {
    std::error_code ec;
    for (const StageOutputs& outputs : kStageOutputs)
      if (outputs.stage == stage)
        for (const char* name : outputs.names) std::filesystem::remove_all(output / name, ec);
    throw;
  }
}

}  // namespace varsfm
