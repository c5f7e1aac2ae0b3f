#include "varsfm/pipeline/stage_model.h"

#include <string>
#include <system_error>

#include <fmt/format.h>

#include "varsfm/io/colmap_model.h"
#include "varsfm/scene/holdout.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

namespace varsfm {

Reconstruction ReadStageModel(std::string_view stage, const std::filesystem::path& sparse,
                              const std::filesystem::path& image_dir, int holdout,
                              size_t min_images) {
  if (!std::filesystem::is_directory(sparse))
    Fail("sparse model folder {} does not exist", sparse.string());
  if (!std::filesystem::is_directory(image_dir))
    Fail("image folder {} does not exist", image_dir.string());
  Reconstruction rec = ReadColmapModel(sparse);
  const size_t held_out = HoldOutImages(&rec, holdout);
  if (held_out > 0) info("{}: {} held-out view(s) left out", stage, held_out);
  const size_t left = rec.NumRegisteredImages();
  if (left < min_images)
    Fail("{}: sparse model {} has {} registered images{}; {} needs at least {}", stage,
         sparse.string(), left + held_out,
         held_out > 0
             ? fmt::format(", {} left once --holdout {} keeps {} out", left, holdout, held_out)
             : std::string(),
         stage, min_images);
  size_t missing = 0;
  std::string first_missing;
  for (const auto& [id, image] : rec.images()) {
    std::error_code error;
    if (!image.registered || std::filesystem::is_regular_file(image_dir / image.name, error))
      continue;
    if (missing++ == 0) first_missing = image.name;
  }
  if (missing > 0)
    Fail("{}: {} of the model's {} registered photos are not in {} (the first: {})", stage, missing,
         left, image_dir.string(), first_missing);
  return rec;
}

}  // namespace varsfm
