#include "varsfm/sfm/track_triangulation.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "varsfm/geometry/triangulation.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

void TrackTriangulationOptions::Check() const {
  CheckPositive("triangulation_max_error_px", max_error_px);
  CheckInRange("min_triangulation_angle_deg", min_angle_deg, 0, 180);
}

namespace {

// The existing 3D point, among those of the registered matches in `corrs`, that reprojects
// best into (image_id, idx) within `max_error`; kInvalidPoint3DId when none does. The matches
// without a 3D point are appended to `fresh`.
point3D_t BestExistingPoint(const Reconstruction& rec, const std::vector<Correspondence>& corrs,
                            image_t image_id, point2D_t idx, double max_error,
                            std::vector<TrackElement>* fresh) {
  point3D_t best_id = kInvalidPoint3DId;
  double best_error = max_error;
  for (const auto& corr : corrs) {
    const Image& other = rec.image(corr.image_id);
    if (!other.registered) continue;
    const point3D_t pid = other.points2D[corr.point2D_idx].point3D_id;
    if (pid == kInvalidPoint3DId) {
      fresh->push_back({corr.image_id, corr.point2D_idx});
      continue;
    }
    const double error =
        std::sqrt(rec.SquaredReprojectionError({image_id, idx}, rec.point3D(pid).xyz));
    if (error < best_error) best_error = error, best_id = pid;
  }
  return best_id;
}

// A new point from every registered view in `fresh` (the new image first): linear multi-view
// triangulation in normalised coordinates, then refinement of the pixel error through each
// camera. Returns whether it was added.
bool AddNewPoint(const TrackTriangulationOptions& options, const std::vector<TrackElement>& fresh,
                 Reconstruction* rec) {
  constexpr double kDegree = std::numbers::pi / 180.0;
  const double min_angle = options.min_angle_deg * kDegree;
  std::vector<Matrix34d> Ps;
  std::vector<Eigen::Vector2d> normalized, pixels;
  std::vector<Camera> cameras;
  std::vector<Rigid3d> poses;
  for (const auto& el : fresh) {
    const Image& im = rec->image(el.image_id);
    Ps.push_back(im.cam_from_world.ToMatrix());
    cameras.push_back(rec->camera(im.camera_id));
    poses.push_back(im.cam_from_world);
    pixels.push_back(im.points2D[el.point2D_idx].xy);
    normalized.push_back(cameras.back().ImageToNormalized(pixels.back()));
  }
  Eigen::Vector3d X;
  if (!TriangulateMultiView(Ps, normalized, &X)) return false;
  RefineTriangulatedPoint(cameras, poses, pixels, &X);
  std::vector<TrackElement> track;
  std::vector<Eigen::Vector3d> centers;
  for (size_t k = 0; k < fresh.size(); ++k) {
    if (!HasPositiveDepth(poses[k], X)) continue;
    if (ReprojectionError(cameras[k], poses[k], pixels[k], X) > options.max_error_px) continue;
    track.push_back(fresh[k]);
    centers.push_back(poses[k].Center());
  }
  if (track.size() < 2 || track.front().image_id != fresh.front().image_id) return false;
  double angle = 0;
  for (size_t a = 0; a < centers.size() && angle < min_angle; ++a)
    for (size_t b = a + 1; b < centers.size() && angle < min_angle; ++b)
      angle = std::max(angle, TriangulationAngle(centers[a], centers[b], X));
  if (angle < min_angle) return false;
  rec->AddPoint3D(X, track);
  return true;
}

}  // namespace

size_t TriangulateImage(const CorrespondenceGraph& graph, const TrackTriangulationOptions& options,
                        image_t image_id, Reconstruction* rec) {
  size_t added = 0;
  const size_t num_points2D = rec->image(image_id).points2D.size();
  for (point2D_t idx = 0; idx < num_points2D; ++idx) {
    if (rec->image(image_id).points2D[idx].HasPoint3D()) continue;
    const auto& corrs = graph.CorrespondencesOf(image_id, idx);
    if (corrs.empty()) continue;
    // Continue an existing track when the point reprojects well here.
    std::vector<TrackElement> fresh = {{image_id, idx}};
    const point3D_t existing =
        BestExistingPoint(*rec, corrs, image_id, idx, options.max_error_px, &fresh);
    if (existing != kInvalidPoint3DId) {
      rec->AddObservation(existing, {image_id, idx});
      continue;
    }
    if (fresh.size() >= 2 && AddNewPoint(options, fresh, rec)) ++added;
  }
  return added;
}

}  // namespace varsfm
