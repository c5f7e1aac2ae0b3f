#include "varsfm/sfm/image_registration.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "varsfm/estimators/absolute_pose_estimator.h"
#include "varsfm/estimators/projection_estimator.h"
#include "varsfm/geometry/projection_decomposition.h"
#include "varsfm/geometry/triangulation.h"
#include "varsfm/sfm/absolute_pose_refinement.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/random.h"

namespace varsfm {

void ImageRegistrationOptions::Check() const {
  CheckAtLeast("--min-correspondences", min_correspondences, 6);
  CheckAtLeast("min_registration_inliers", min_inliers, 6);
  CheckFraction("registration.min_inlier_ratio", min_inlier_ratio);
  if (relaxed_min_inliers != 0)
    CheckInRange("registration.relaxed_min_inliers", relaxed_min_inliers, 6, min_inliers);
  CheckFraction("registration.relaxed_min_inlier_ratio", relaxed_min_inlier_ratio);
  CheckPositive("registration_max_error_px", max_error_px);
  CheckAtLeast("registration.refinement_gate_factor", refinement_gate_factor, 1);
  CheckAtLeast("registration.pnp_max_iterations", pnp_max_iterations, 1);
  CheckFraction("registration.pnp_confidence", pnp_confidence);
  CheckPositive("registration.min_focal_factor", min_focal_factor);
  CheckGreaterThan("registration.max_focal_factor", max_focal_factor, min_focal_factor);
  CheckPositive("registration.dlt_min_focal_factor", dlt_min_focal_factor);
  CheckGreaterThan("registration.dlt_max_focal_factor", dlt_max_focal_factor, dlt_min_focal_factor);
  CheckPositive("registration.dlt_min_aspect", dlt_min_aspect);
  CheckGreaterThan("registration.dlt_max_aspect", dlt_max_aspect, dlt_min_aspect);
  CheckPositive("registration.dlt_max_skew_fraction", dlt_max_skew_fraction);
  CheckPositive("registration.dlt_max_principal_point_offset", dlt_max_principal_point_offset);
  CheckFraction("registration.free_principal_point_max_cost_ratio",
                free_principal_point_max_cost_ratio);
  CheckNonNegative("registration.free_principal_point_min_offset", free_principal_point_min_offset);
}

std::vector<Correspondence2D3D> FindCorrespondences2D3D(const CorrespondenceGraph& graph,
                                                        const Reconstruction& rec,
                                                        image_t image_id) {
  const Image& image = rec.image(image_id);
  std::vector<Correspondence2D3D> corrs;
  for (point2D_t idx = 0; idx < image.points2D.size(); ++idx) {
    for (const auto& corr : graph.CorrespondencesOf(image_id, idx)) {
      const Image& other = rec.image(corr.image_id);
      if (!other.registered) continue;
      const point3D_t pid = other.points2D[corr.point2D_idx].point3D_id;
      if (pid == kInvalidPoint3DId) continue;
      corrs.push_back({idx, pid});
      break;
    }
  }
  return corrs;
}

namespace {

// Whether a K from the DLT decomposition is physically plausible for this image, its principal
// point within `max_principal_point_offset` x the larger side of the centre.
bool PlausibleCalibration(const ImageRegistrationOptions& o, const Eigen::Matrix3d& K,
                          const Camera& camera, double max_principal_point_offset) {
  const double size = std::max(camera.width, camera.height);
  const double f = K(0, 0);
  const double aspect = K(1, 1) / K(0, 0);
  const Eigen::Vector2d pp(K(0, 2), K(1, 2));
  const Eigen::Vector2d centre(camera.width / 2.0, camera.height / 2.0);
  return f > o.dlt_min_focal_factor * size && f < o.dlt_max_focal_factor * size &&
         aspect > o.dlt_min_aspect && aspect < o.dlt_max_aspect &&
         std::abs(K(0, 1)) < o.dlt_max_skew_fraction * f &&
         (pp - centre).norm() < max_principal_point_offset * size;
}

struct Hypothesis {
  Camera camera;
  Rigid3d pose;
  size_t inliers = 0;
  // Sum over the correspondences of the squared reprojection error, capped at the inlier
  // threshold's square (MSAC's score, Torr & Zisserman 2000).
  double truncated_cost = 0;
};

// Scores `h` on the correspondences: its inliers and truncated cost.
void Score(const std::vector<Eigen::Vector2d>& x, const std::vector<Eigen::Vector3d>& X,
           double max_error, Hypothesis* h) {
  h->inliers = 0;
  h->truncated_cost = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double e = ReprojectionError(h->camera, h->pose, x[i], X[i]);
    if (e <= max_error) ++h->inliers;
    h->truncated_cost += std::min(e, max_error) * std::min(e, max_error);
  }
}

// What the hypotheses of one image are made from and refined with.
struct RegistrationProblem {
  const ImageRegistrationOptions& options;
  const IntrinsicsPolicy& intrinsics;
  image_t image_id;
  uint64_t seed;
  std::vector<Eigen::Vector2d> x;  // the correspondences' 2D points
  std::vector<Eigen::Vector3d> X;  // and their 3D points
  Camera camera;                   // the image's camera as it is
  // Where the hypotheses' intrinsics start (StartingCamera): the camera itself when a registered
  // image uses it, else the neighbour's intrinsics (zoom changes slowly along a capture).
  Camera start_camera;
  bool camera_registered;  // a registered image uses the camera: its intrinsics are held
  AbsolutePoseRefinementOptions refine;
  // The refinement frees the principal point, which the policy holds (FreePrincipalPoint).
  bool free_principal_point = false;
};

// Refines `h` on the correspondences near it and scores it on all; appends it when refined.
void RefineAndScore(const RegistrationProblem& p, Hypothesis h, std::vector<Hypothesis>* out) {
  std::vector<Eigen::Vector2d> xi;
  std::vector<Eigen::Vector3d> Xi;
  for (size_t i = 0; i < p.x.size(); ++i)
    if (ReprojectionError(h.camera, h.pose, p.x[i], p.X[i]) <=
        p.options.refinement_gate_factor * p.options.max_error_px) {
      xi.push_back(p.x[i]);
      Xi.push_back(p.X[i]);
    }
  // Six points: the most parameters the refinement frees (pose and up to five intrinsics) need
  // at least as many equations.
  if (xi.size() < 6 || !RefineAbsolutePose(p.refine, xi, Xi, &h.camera, &h.pose)) return;
  Score(p.x, p.X, p.options.max_error_px, &h);
  out->push_back(h);
}

// The paper's projection matrix (section 4.3): RANSAC + DLT, decomposed into K, R, t.
struct DltEstimate {
  Eigen::Matrix3d K;
  Rigid3d pose;
};

std::optional<DltEstimate> EstimateDlt(const RegistrationProblem& p) {
  RansacOptions ransac;
  ransac.max_error = p.options.max_error_px;
  ransac.seed = DeriveSeed(p.seed, p.image_id);
  const auto p_report = EstimateProjectionMatrix(p.x, p.X, ransac);
  if (!p_report.success) return std::nullopt;
  Eigen::Matrix3d K, R;
  Eigen::Vector3d t;
  if (!DecomposeProjectionMatrix(p_report.model, &K, &R, &t)) return std::nullopt;
  return DltEstimate{K, Rigid3d(R, t)};
}

// (a) The DLT's pose, its K starting the refinement where it is plausible for the image. With
// p.free_principal_point, K's principal point may lie anywhere within the circle through the
// image's corners.
void AddDltHypothesis(const RegistrationProblem& p, const DltEstimate& dlt,
                      std::vector<Hypothesis>* out) {
  const Eigen::Matrix3d& K = dlt.K;
  const double max_pp_offset = p.free_principal_point
                                   ? 0.5 * std::hypot(p.camera.width, p.camera.height) /
                                         std::max(p.camera.width, p.camera.height)
                                   : p.options.dlt_max_principal_point_offset;
  Hypothesis h{p.start_camera, dlt.pose, 0};
  if (!p.camera_registered && PlausibleCalibration(p.options, K, p.camera, max_pp_offset)) {
    // Keep the held parameters at their initial values (policy), take the rest from K.
    Camera from_dlt = p.camera;
    from_dlt.params[Camera::kK1] = p.start_camera.params[Camera::kK1];
    from_dlt.params[Camera::kK2] = p.start_camera.params[Camera::kK2];
    from_dlt.focal() = 0.5 * (K(0, 0) + K(1, 1));
    if (p.intrinsics.refine_aspect) from_dlt.params[Camera::kAspect] = K(1, 1) / K(0, 0);
    if (p.intrinsics.refine_skew) from_dlt.params[Camera::kSkew] = K(0, 1);
    // Parameters shared per image size start from the group's current values (the neighbour's
    // when it has this size; StartingCamera keeps the image's own otherwise).
    for (const int i : p.intrinsics.SharedPerSize()) from_dlt.params[i] = p.start_camera.params[i];
    if (p.intrinsics.refine_principal_point || p.free_principal_point) {
      from_dlt.params[Camera::kU0] = K(0, 2);
      from_dlt.params[Camera::kV0] = K(1, 2);
    }
    h.camera = from_dlt;
  }
  RefineAndScore(p, h, out);
}

// (b) PnP with the neighbour's intrinsics (robust on nearly planar point sets, where the DLT is
// ill-posed): LO-RANSAC around P3P on normalised coordinates, then the same refinement frees
// the focal length.
void AddPnpHypothesis(const RegistrationProblem& p, std::vector<Hypothesis>* out) {
  const Camera& start = p.start_camera;
  std::vector<Eigen::Vector2d> normalized;
  normalized.reserve(p.x.size());
  for (const Eigen::Vector2d& x : p.x) normalized.push_back(start.ImageToNormalized(x));
  RansacOptions ransac;
  ransac.max_error = start.ImageToNormalizedThreshold(p.options.max_error_px);
  ransac.confidence = p.options.pnp_confidence;
  ransac.max_iterations = p.options.pnp_max_iterations;
  // A stream of its own, apart from the DLT's (seeded by the image id).
  ransac.seed = DeriveSeed(DeriveSeed(p.seed, p.image_id), 1);
  const auto report = Ransac(AbsolutePoseEstimator{normalized, p.X}, ransac);
  if (!report.success) return;
  RefineAndScore(p, {start, report.model, 0}, out);
}

// The intrinsics a new image's hypotheses start from: its registered neighbour's when the two
// images have the same size. Another size (another phone, a resized copy) takes the neighbour's
// focal length scaled by the ratio of the larger sides (the same field of view) and its k1, k2
// (on normalised coordinates, so independent of the resolution), and the principal point, aspect
// and skew of `same_size`, a registered camera of the image's size, or else keeps its own. A
// principal point taken from a photo of another size would lie off this one's centre by the
// difference of the two, and a size with fewer images than the adjustments' min_images_to_share
// would keep it.
Camera StartingCamera(const Camera& camera, const Camera& neighbour, const Camera* same_size) {
  if (neighbour.width == camera.width && neighbour.height == camera.height) {
    Camera start = neighbour;
    start.camera_id = camera.camera_id;
    return start;
  }
  Camera start = camera;
  if (same_size)
    for (const int i : {Camera::kU0, Camera::kV0, Camera::kAspect, Camera::kSkew})
      start.params[i] = same_size->params[i];
  start.focal() = neighbour.focal() * std::max(camera.width, camera.height) /
                  std::max(neighbour.width, neighbour.height);
  start.params[Camera::kK1] = neighbour.params[Camera::kK1];
  start.params[Camera::kK2] = neighbour.params[Camera::kK2];
  return start;
}

// The camera of the most recently registered image with `camera`'s size (null: none).
const Camera* SameSizeCamera(const Reconstruction& rec, const Camera& camera,
                             const std::vector<image_t>& registration_order) {
  for (auto it = registration_order.rbegin(); it != registration_order.rend(); ++it) {
    const Camera& other = rec.CameraOf(*it);
    if (other.width == camera.width && other.height == camera.height) return &other;
  }
  return nullptr;
}

// The first image of its size (a cropped photo, another phone) has no registered principal point
// to start from, and the policy holds it at the centre. The DLT's and the chosen hypothesis are
// refined once more with the principal point free; the one of lower truncated cost replaces the
// chosen one when its cost is at most options.free_principal_point_max_cost_ratio of it and its
// principal point lies at least options.free_principal_point_min_offset x the larger side from
// the centre. A photo cut off-centre fits with a centred principal point only through a wrong
// focal length and rotation, at several times its noise. Nearer the centre the adjustments cope
// with a centred start, and two more parameters also absorb the errors of a young model's
// structure (a few pixels off the centre on a degenerate initial pair).
void FreePrincipalPoint(const RegistrationProblem& p, const std::optional<DltEstimate>& dlt,
                        Hypothesis* chosen) {
  RegistrationProblem free = p;
  free.free_principal_point = true;
  free.refine.intrinsics.refine_principal_point = true;
  std::vector<Hypothesis> freed;
  if (dlt) AddDltHypothesis(free, *dlt, &freed);
  RefineAndScore(free, *chosen, &freed);
  if (freed.empty()) return;
  const Hypothesis& best = *std::min_element(
      freed.begin(), freed.end(),
      [](const Hypothesis& a, const Hypothesis& b) { return a.truncated_cost < b.truncated_cost; });
  const double offset =
      best.camera.PrincipalPointOffset().norm() / std::max(best.camera.width, best.camera.height);
  if (best.truncated_cost >
          p.options.free_principal_point_max_cost_ratio * chosen->truncated_cost ||
      offset < p.options.free_principal_point_min_offset)
    return;
  debug("image {}: principal point ({:.1f}, {:.1f}) of its own, truncated cost {:.1f} -> {:.1f}",
        p.image_id, best.camera.params[Camera::kU0], best.camera.params[Camera::kV0],
        chosen->truncated_cost, best.truncated_cost);
  *chosen = best;
}

// The registered image that shares the most 3D points with the correspondences (the most
// recent registration when none does).
image_t Neighbour(const Reconstruction& rec, const std::vector<Correspondence2D3D>& corrs,
                  const std::vector<image_t>& registration_order) {
  std::map<image_t, size_t> shared_points;
  for (const auto& c : corrs)
    for (const auto& el : rec.point3D(c.point3D_id).track) ++shared_points[el.image_id];
  image_t neighbour = registration_order.back();
  size_t best = 0;
  for (const auto& [id, count] : shared_points)
    if (count > best) best = count, neighbour = id;
  return neighbour;
}

}  // namespace

bool RegisterImage(const CorrespondenceGraph& graph, const ImageRegistrationOptions& options,
                   const IntrinsicsPolicy& intrinsics,
                   const std::vector<image_t>& registration_order, uint64_t seed, image_t image_id,
                   Reconstruction* rec) {
  Image& image = rec->image(image_id);
  const std::vector<Correspondence2D3D> corrs = FindCorrespondences2D3D(graph, *rec, image_id);
  if (corrs.size() < static_cast<size_t>(std::max(options.min_correspondences, 6))) return false;
  Camera& camera = rec->CameraOf(image_id);
  const bool camera_registered =
      std::any_of(registration_order.begin(), registration_order.end(),
                  [&](image_t other) { return rec->image(other).camera_id == image.camera_id; });
  const Camera* same_size = SameSizeCamera(*rec, camera, registration_order);
  RegistrationProblem problem{
      .options = options,
      .intrinsics = intrinsics,
      .image_id = image_id,
      .seed = seed,
      .x = {},
      .X = {},
      .camera = camera,
      .start_camera =
          camera_registered
              ? camera
              : StartingCamera(camera, rec->CameraOf(Neighbour(*rec, corrs, registration_order)),
                               same_size),
      .camera_registered = camera_registered,
      .refine = {}};
  for (const auto& c : corrs) {
    problem.x.push_back(image.points2D[c.point2D_idx].xy);
    problem.X.push_back(rec->point3D(c.point3D_id).xyz);
  }
  problem.refine.intrinsics = intrinsics.ForRegistration(camera_registered);

  std::vector<Hypothesis> hypotheses;
  const std::optional<DltEstimate> dlt = EstimateDlt(problem);
  if (dlt) AddDltHypothesis(problem, *dlt, &hypotheses);
  AddPnpHypothesis(problem, &hypotheses);
  if (hypotheses.empty()) return false;
  // The first of the best: the DLT's on a tie.
  Hypothesis chosen = *std::max_element(
      hypotheses.begin(), hypotheses.end(),
      [](const Hypothesis& a, const Hypothesis& b) { return a.inliers < b.inliers; });
  if (!camera_registered && !same_size && !problem.refine.intrinsics.refine_principal_point &&
      options.free_principal_point_max_cost_ratio > 0)
    FreePrincipalPoint(problem, dlt, &chosen);
  if (chosen.inliers < static_cast<size_t>(options.min_inliers) ||
      chosen.inliers < options.min_inlier_ratio * corrs.size())
    return false;
  const double size = std::max(camera.width, camera.height);
  if (chosen.camera.focal() < options.min_focal_factor * size ||
      chosen.camera.focal() > options.max_focal_factor * size)
    return false;

  if (!camera_registered) camera.params = chosen.camera.params;
  image.cam_from_world = chosen.pose;
  rec->RegisterImage(image_id);
  for (size_t i = 0; i < corrs.size(); ++i)
    if (ReprojectionError(camera, image.cam_from_world, problem.x[i], problem.X[i]) <=
        options.max_error_px)
      rec->AddObservation(corrs[i].point3D_id, {image_id, corrs[i].point2D_idx});
  debug("registered image {} ({}) with {} inliers of {}, f {:.1f}", image_id, image.name,
        chosen.inliers, corrs.size(), camera.focal());
  return true;
}

}  // namespace varsfm
