#pragma once
// How many reconstructed points each image sees through the correspondence graph: the number of
// its 2D points that have a correspondence at a 2D point of a registered image with a 3D point,
// the next-best-view score of the incremental mapper. Kept up to date as the model changes
// (ReconstructionObserver) rather than recounted over every unregistered image after each
// registration, which on an unordered collection, where every image soon matches a registered
// one, made the choice of the next image quadratic in the number of images. COLMAP keeps the
// same counts for the same reason (Schoenberger & Frahm, "Structure-from-Motion Revisited",
// CVPR 2016, sec. 4.2: the next-best-view scores are updated incrementally).
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "varsfm/scene/reconstruction.h"
#include "varsfm/sfm/correspondence_graph.h"

namespace varsfm {

class VisiblePointCounts : public ReconstructionObserver {
 public:
  explicit VisiblePointCounts(const CorrespondenceGraph& graph) : graph_(graph) {}

  // Counts from scratch for the model as it is.
  void Recount(const Reconstruction& rec);

  // The image's score: its 2D points with at least one correspondence at a registered image's
  // 2D point that has a 3D point (0 for an image not in the graph).
  size_t VisiblePoints(image_t image_id) const;

  void PointTriangulationChanged(const Image& image, point2D_t idx, bool triangulated) override;
  void ImageRegistrationChanged(const Image& image) override;

 private:
  struct Counts {
    std::vector<uint32_t> per_point;  // per 2D point: its correspondences that see a 3D point
    size_t visible = 0;               // 2D points whose count is not 0
  };
  // Adds `delta` (+1 / -1) to the count of every correspondence of (image_id, idx).
  void Update(image_t image_id, point2D_t idx, int delta);

  const CorrespondenceGraph& graph_;
  std::unordered_map<image_t, Counts> counts_;
};

// Attaches `counts` to `rec` (recounted) for the lifetime of the guard.
class ObservedReconstruction {
 public:
  ObservedReconstruction(Reconstruction* rec, VisiblePointCounts* counts) : rec_(rec) {
    counts->Recount(*rec);
    rec->SetObserver(counts);
  }
  ~ObservedReconstruction() { rec_->SetObserver(nullptr); }
  ObservedReconstruction(const ObservedReconstruction&) = delete;
  ObservedReconstruction& operator=(const ObservedReconstruction&) = delete;

 private:
  Reconstruction* rec_;
};

}  // namespace varsfm
