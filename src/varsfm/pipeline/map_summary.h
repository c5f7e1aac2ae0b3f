#pragma once
// The content of `map`'s summary.json: model 0's figures at the top level (as when there was
// only one model), every image with the model that holds it or why none does, and each model's
// figures under "models".
#include <vector>

#include <nlohmann/json.hpp>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/sfm/multi_model_mapper.h"

namespace varsfm {

// A reconstruction's figures and its images (intrinsics and centre of the registered ones).
nlohmann::json ReconstructionSummaryJson(const Reconstruction& reconstruction);

// `models` largest first, as ReconstructAllModels returns them (at least one); their
// reconstructions together hold every image. Stage timings are added by the caller.
nlohmann::json MapSummaryJson(const std::vector<MapperModel>& models,
                              const std::vector<UnmodelledImage>& unmodelled);

}  // namespace varsfm
