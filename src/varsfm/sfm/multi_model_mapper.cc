#include "varsfm/sfm/multi_model_mapper.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>

#include <fmt/format.h>

#include "varsfm/util/log.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

// The images `ids` of the first model (which holds every image), unregistered and without
// links to its points, with their cameras as they were before any run (`priors`: a camera
// shared with images of an earlier model starts again from its prior), and the verified matches
// among them only: a run on these cannot reach an image outside. Taken from the first model
// rather than from a copy of the input, which would double the keypoints held.
struct RemainingImages {
  Reconstruction reconstruction;
  CorrespondenceGraph graph;
};

RemainingImages SelectImages(const Reconstruction& first, const std::map<camera_t, Camera>& priors,
                             const CorrespondenceGraph& graph, const std::set<image_t>& ids) {
  RemainingImages remaining;
  for (const image_t id : ids) {
    Image image = first.image(id);
    image.registered = false;
    image.cam_from_world = Rigid3d();
    for (Point2D& point : image.points2D) point.point3D_id = kInvalidPoint3DId;
    if (!remaining.reconstruction.ExistsCamera(image.camera_id))
      remaining.reconstruction.AddCamera(priors.at(image.camera_id));
    remaining.reconstruction.AddImage(std::move(image));
    remaining.graph.AddImage(id, graph.NumPoints2D(id));
  }
  for (const auto& [pair, count] : graph.PairCounts())
    if (ids.count(pair.first) && ids.count(pair.second))
      remaining.graph.AddImagePair(pair.first, pair.second,
                                   graph.MatchesBetween(pair.first, pair.second),
                                   graph.FundamentalMatrix(pair.first, pair.second));
  return remaining;
}

// The images no model holds that share verified matches with another of them: those a further
// run can start from or register.
std::set<image_t> ConnectedRemainingImages(const CorrespondenceGraph& graph,
                                           const std::set<image_t>& modelled) {
  std::set<image_t> ids;
  for (const auto& [pair, count] : graph.PairCounts())
    if (!modelled.count(pair.first) && !modelled.count(pair.second)) {
      ids.insert(pair.first);
      ids.insert(pair.second);
    }
  return ids;
}

// Why an image is in no model, from its verified matches and the models its neighbours are in.
std::string UnmodelledReason(image_t id, const CorrespondenceGraph& graph,
                             const std::map<image_t, size_t>& model_of,
                             const std::string& last_message) {
  if (!graph.ExistsImage(id) || graph.NeighborsOf(id).empty())
    return "no verified matches with any other image";
  size_t model = SIZE_MAX;
  for (const image_t neighbor : graph.NeighborsOf(id)) {
    const auto it = model_of.find(neighbor);
    if (it != model_of.end()) model = std::min(model, it->second);
  }
  if (model != SIZE_MAX)
    return fmt::format(
        "matches images of model {} but could not be registered (too few 2D-3D correspondences "
        "or inliers)",
        model);
  return "no model could start from the images it matches: " + last_message;
}

}  // namespace

MultiModelResult ReconstructAllModels(
    Reconstruction input, const CorrespondenceGraph& graph,
    const std::vector<std::pair<image_t, image_t>>& excluded_initial_pairs,
    const IncrementalMapperOptions& options) {
  MultiModelResult result;
  const std::map<camera_t, Camera> priors = input.cameras();
  const size_t num_images = input.images().size();
  std::set<image_t> modelled;
  std::vector<image_t> all_ids;  // every image, from the first model
  for (size_t run = 0;; ++run) {
    Timer timer;
    MapperModel model;
    model.build_order = run;
    // The progress counts the images of every model so far against all images.
    IncrementalMapperOptions run_options = options;
    if (options.progress)
      run_options.progress = [&options, offset = modelled.size(), total = num_images](
                                 size_t registered, size_t, double rms) {
        options.progress(offset + registered, total, rms);
      };
    if (run == 0) {
      // The single-model mapper's run, on the input as it is.
      model.reconstruction = std::move(input);
      IncrementalMapper mapper(graph, excluded_initial_pairs, run_options);
      model.summary = mapper.Reconstruct(&model.reconstruction);
    } else {
      const std::set<image_t> ids = ConnectedRemainingImages(graph, modelled);
      if (ids.size() < 2) break;
      // models.front() is the first run's until the sort below.
      RemainingImages remaining =
          SelectImages(result.models.front().reconstruction, priors, graph, ids);
      std::vector<std::pair<image_t, image_t>> excluded;
      for (const auto& pair : excluded_initial_pairs)
        if (ids.count(pair.first) && ids.count(pair.second)) excluded.push_back(pair);
      info("map: starting another model from the {} images no model holds", ids.size());
      IncrementalMapper mapper(remaining.graph, excluded, run_options);
      model.reconstruction = std::move(remaining.reconstruction);
      model.summary = mapper.Reconstruct(&model.reconstruction);
    }
    model.seconds = timer.Seconds();
    if (!model.summary.success) {
      result.message = model.summary.message;
      break;
    }
    if (run == 0)
      for (const auto& [id, image] : model.reconstruction.images()) all_ids.push_back(id);
    for (const image_t id : model.reconstruction.RegisteredImageIds()) modelled.insert(id);
    result.models.push_back(std::move(model));
  }
  std::stable_sort(result.models.begin(), result.models.end(),
                   [](const MapperModel& a, const MapperModel& b) {
                     return a.summary.num_registered > b.summary.num_registered;
                   });

  std::map<image_t, size_t> model_of;
  for (size_t k = 0; k < result.models.size(); ++k)
    for (const image_t id : result.models[k].reconstruction.RegisteredImageIds()) model_of[id] = k;
  for (const image_t id : all_ids)
    if (!model_of.count(id))
      result.unmodelled.push_back({id, UnmodelledReason(id, graph, model_of, result.message)});
  return result;
}

}  // namespace varsfm
