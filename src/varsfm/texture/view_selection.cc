#include "varsfm/texture/view_selection.h"

#include <algorithm>
#include <limits>

#include "varsfm/texture/alpha_expansion.h"
#include "varsfm/texture/face_adjacency.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

ViewSelection SelectViews(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<Eigen::Vector3i>& faces,
                          const std::vector<PosedCamera>& views,
                          const std::function<cv::Mat(size_t)>& load_image,
                          const ViewSelectionOptions& options) {
  FaceObservations obs = ObserveFaces(vertices, faces, views, load_image, options.observation);
  ViewSelection selection;
  selection.gains = EstimateExposureGains(obs, options.exposure);
  selection.neighbours = FaceNeighbours(faces);
  const std::vector<std::array<int, 3>>& neighbours = selection.neighbours;
  selection.num_rejected_observations =
      RejectInconsistentViews(selection.gains, neighbours, options.consistency, &obs);

  // Data term: 1 - quality / the face's best quality, plus the consensus term, for every view
  // that may texture it.
  PottsProblem problem;
  problem.num_labels = static_cast<int>(views.size());
  problem.potts = options.smoothness;
  problem.neighbours = neighbours;
  problem.offsets.reserve(faces.size() + 1);
  const double deviation_scale =
      1.0 / (options.consistency.reject_distance * options.consistency.bandwidth);
  std::vector<int> best_view(faces.size(), -1);
  for (size_t f = 0; f < faces.size(); ++f) {
    const size_t first = obs.begin[f], last = obs.begin[f + 1];  // in view order
    float best = 0;
    for (size_t k = first; k < last; ++k) best = std::max(best, obs.quality[k]);
    float lowest = std::numeric_limits<float>::max(), lowest_quality = 0;
    for (size_t k = first; k < last; ++k) {
      const float quality = obs.quality[k];
      if (quality <= 0) continue;
      const int v = static_cast<int>(obs.view[k]);
      const double deviation = std::min(1.0, obs.deviation[k] * deviation_scale);
      const float cost =
          static_cast<float>(1.0 - quality / best + options.consensus_weight * deviation);
      problem.candidate_labels.push_back(v);
      problem.candidate_costs.push_back(cost);
      // Ties go to the higher quality (the face's best view when the consensus term is off).
      if (cost < lowest || (cost == lowest && quality > lowest_quality)) {
        lowest = cost;
        lowest_quality = quality;
        best_view[f] = v;
      }
    }
    problem.offsets.push_back(problem.candidate_labels.size());
    if (best_view[f] >= 0) ++selection.num_visible_faces;
  }
  selection.labels = best_view;
  if (options.smoothness > 0)
    ExpandLabels(problem, options.max_expansion_cycles, &selection.labels,
                 options.expansion_tolerance, "texture: view selection");
  for (size_t f = 0; f < faces.size(); ++f)
    selection.num_changed_by_smoothing += selection.labels[f] != best_view[f];
  selection.coverage = std::move(obs.coverage);
  selection.small_photos = std::move(obs.small_photos);
  selection.small_scale = std::move(obs.small_scale);
  return selection;
}

void ViewSelectionOptions::Check() const {
  observation.Check();
  exposure.Check();
  consistency.Check();
  CheckNonNegative("--smoothness", smoothness);
  CheckNonNegative("--consensus-weight", consensus_weight);
  CheckNonNegative("max_expansion_cycles", max_expansion_cycles);
  CheckFraction("expansion_tolerance", expansion_tolerance);
}

}  // namespace varsfm
