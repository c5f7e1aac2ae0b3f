#include "varsfm/pipeline/stage_model.h"

#include "varsfm/io/colmap_model.h"
#include "varsfm/scene/holdout.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

namespace varsfm {

Reconstruction ReadStageModel(std::string_view stage, const std::filesystem::path& sparse,
                              const std::filesystem::path& image_dir, int holdout) {
  if (!std::filesystem::is_directory(sparse))
    Fail("sparse model folder {} does not exist", sparse.string());
  if (!std::filesystem::is_directory(image_dir))
    Fail("image folder {} does not exist", image_dir.string());
  Reconstruction rec = ReadColmapModel(sparse);
  if (const size_t n = HoldOutImages(&rec, holdout))
    info("{}: {} held-out view(s) left out", stage, n);
  return rec;
}

}  // namespace varsfm
