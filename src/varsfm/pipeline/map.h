#pragma once
// Stage 3 of the pipeline: the workspace's features and verified matches in, a sparse model out
// (OUT/sparse/0/ as COLMAP text + binary, OUT/sparse.ply, OUT/bundle.out + list.txt,
// OUT/summary.json).
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "varsfm/pipeline/map_summary.h"
#include "varsfm/scene/reconstruction.h"
#include "varsfm/sfm/incremental_mapper.h"
#include "varsfm/sfm/multi_model_mapper.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

struct MapOptions {
  std::filesystem::path workspace;
  std::filesystem::path output;
  std::filesystem::path image_dir;  // optional: colours of the points are read from the images
  IncrementalMapperOptions mapper;  // its `intrinsics.sharing` also decides how cameras load
  int min_pair_inliers = 15;        // pairs with fewer verified matches are ignored

  // Throws OptionError (util/option_check.h) for a bad value; files are checked when the stage
  // runs.
  void Check() const;
};

struct MapSummary {
  // Model 0 (OUT/sparse/0, the one the other outputs describe): the largest. It holds every
  // image when it was the first built, else only those left for it (num_images counts all).
  MapperSummary mapper;
  Reconstruction reconstruction;
  size_t num_images = 0;  // in the workspace, with features
  // Models 1, 2, ... (OUT/sparse/1, ...): of the images model 0 could not register, as COLMAP's
  // mapper builds them (sfm/multi_model_mapper.h); and the images in no model, with why.
  std::vector<MapperModel> more_models;
  std::vector<UnmodelledImage> unmodelled;
  double seconds = 0;  // the whole stage: loading, mapping, writing
  double seconds_mapping = 0;
};

// Loads the workspace, reconstructs, writes the outputs. Throws varsfm::Error (one line) when the
// workspace is missing or holds fewer than two images with features, or when no pair can
// initialise: nothing is written in that case (an existing OUT is left as it was).
MapSummary RunMapping(const MapOptions& options, OptionsCheck check = OptionsCheck::kByStage);

}  // namespace varsfm
