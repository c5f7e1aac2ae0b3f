#pragma once
// Every model the images allow, as COLMAP's mapper builds them: the incremental mapper runs on
// all images; when it can register no more, it starts again from the images no model holds (a
// new initial pair among them, by the same criterion), until no initial pair can be found. A
// folder of photos of two unrelated scenes thus gives one model of each, instead of one model
// and images dropped without a word.
//
// The first run is the single-model mapper's run on the same input, so a connected scene gives
// the same model as before, bit for bit. The models are returned largest first (most registered
// images; the earlier built first among equals), each image in at most one of them.
#include <string>
#include <utility>
#include <vector>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/sfm/correspondence_graph.h"
#include "varsfm/sfm/incremental_mapper.h"

namespace varsfm {

struct MapperModel {
  // The first model built holds every image of the input (those it did not register too, as
  // the single-model mapper's); a later one holds the images that were left for it.
  Reconstruction reconstruction;
  MapperSummary summary;
  size_t build_order = 0;  // 0: the run on all images
  double seconds = 0;      // the run that built it
};

// An image that no model registered, and why.
struct UnmodelledImage {
  image_t image_id = kInvalidImageId;
  std::string reason;  // one line
};

struct MultiModelResult {
  std::vector<MapperModel> models;          // largest first; empty when none could start
  std::vector<UnmodelledImage> unmodelled;  // in image id order (empty when models is)
  std::string message;  // why the mapper stopped starting models (the last run's message)
};

// `input` holds every image (unregistered) with its camera, as IncrementalMapper::Reconstruct
// takes it; `graph` and `excluded_initial_pairs` as for IncrementalMapper. The options'
// progress callback counts the images registered in all models so far against all images.
MultiModelResult ReconstructAllModels(
    Reconstruction input, const CorrespondenceGraph& graph,
    const std::vector<std::pair<image_t, image_t>>& excluded_initial_pairs,
    const IncrementalMapperOptions& options);

}  // namespace varsfm
