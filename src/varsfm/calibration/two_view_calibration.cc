#include "varsfm/calibration/two_view_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "varsfm/ba/bundle_adjuster.h"
#include "varsfm/calibration/bougnoux.h"
#include "varsfm/geometry/essential.h"
#include "varsfm/geometry/triangulation.h"

namespace varsfm {

std::optional<std::pair<double, double>> ClosedFormFocalLengths(
    const Eigen::Matrix3d& F, int width1, int height1, int width2, int height2,
    const TwoViewCalibrationOptions& o, std::string* reason) {
  const Camera c1 = Camera::FromFocal(width1, height1, 1.0);
  const Camera c2 = Camera::FromFocal(width2, height2, 1.0);
  const Eigen::Vector2d pp1(c1.width / 2.0, c1.height / 2.0);
  const Eigen::Vector2d pp2(c2.width / 2.0, c2.height / 2.0);
  const auto focals = BougnouxFocalLengths(F, pp1, pp2);
  if (!focals) {
    *reason = "negative squared focal length";
    return std::nullopt;
  }
  const double size1 = std::max(c1.width, c1.height), size2 = std::max(c2.width, c2.height);
  const auto in_range = [&](double f, double size) {
    return f >= o.min_focal_factor * size && f <= o.max_focal_factor * size;
  };
  if (!in_range(focals->first, size1) || !in_range(focals->second, size2)) {
    *reason = fmt::format("focal lengths {:.0f}, {:.0f} px outside the plausible range",
                          focals->first, focals->second);
    return std::nullopt;
  }
  // Sensitivity to the principal points (held at the centres, which is only approximately
  // true): when the optical axes are nearly coplanar the closed form explodes.
  const double d1 = o.principal_point_perturbation * size1;
  const double d2 = o.principal_point_perturbation * size2;
  double worst = 0;
  for (const Eigen::Vector2d delta : {Eigen::Vector2d(1, 0), Eigen::Vector2d(0, 1),
                                      Eigen::Vector2d(-1, 0), Eigen::Vector2d(0, -1)}) {
    for (int which = 0; which < 2; ++which) {
      const auto moved = BougnouxFocalLengths(F, pp1 + (which == 0 ? d1 : 0) * delta,
                                              pp2 + (which == 1 ? d2 : 0) * delta);
      if (!moved) {
        worst = std::numeric_limits<double>::infinity();
        continue;
      }
      worst = std::max({worst, std::abs(std::log(moved->first / focals->first)),
                        std::abs(std::log(moved->second / focals->second))});
    }
  }
  if (worst > o.max_focal_sensitivity) {
    *reason = fmt::format(
        "ill-conditioned (optical axes nearly coplanar: log f changes by {:.2f} when a principal "
        "point moves by {:.0f} %)",
        worst, 100 * o.principal_point_perturbation);
    return std::nullopt;
  }
  return focals;
}

TwoViewCalibration CalibrateTwoView(const std::vector<Eigen::Vector2d>& x1,
                                    const std::vector<Eigen::Vector2d>& x2, int width1,
                                    int height1, int width2, int height2,
                                    const Eigen::Matrix3d& F,
                                    const TwoViewCalibrationOptions& o) {
  TwoViewCalibration result;
  if (x1.size() != x2.size() || x1.size() < 8) return result;
  Camera c1 = Camera::FromFocal(width1, height1, 1.0);
  Camera c2 = Camera::FromFocal(width2, height2, 1.0);
  c1.camera_id = 1;
  c2.camera_id = 2;

  const auto focals =
      ClosedFormFocalLengths(F, width1, height1, width2, height2, o, &result.degeneracy_reason);
  if (focals) {
    c1.focal() = focals->first;
    c2.focal() = focals->second;
  } else {
    result.degenerate = true;
    c1.focal() = o.prior_focal1.value_or(o.prior_focal_factor * std::max(width1, height1));
    c2.focal() = o.prior_focal2.value_or(o.prior_focal_factor * std::max(width2, height2));
  }

  // E = K2^T F K1 (eq. 22), then the pose with the most points in front of both cameras.
  const Eigen::Matrix3d E = ProjectToEssential(c2.K().transpose() * F * c1.K());
  std::vector<Eigen::Vector2d> n1, n2;
  for (size_t i = 0; i < x1.size(); ++i) {
    n1.push_back(c1.ImageToNormalized(x1[i]));
    n2.push_back(c2.ImageToNormalized(x2[i]));
  }
  Rigid3d pose;
  if (PoseFromEssentialMatrix(E, n1, n2, &pose) < 8) return result;

  // Two-view bundle adjustment (eq. 34) on a two-image reconstruction: focal lengths (held
  // when degenerate: two views cannot fix them then), k1, k2, the pose and the points.
  Reconstruction rec;
  rec.AddCamera(c1);
  rec.AddCamera(c2);
  for (int k = 0; k < 2; ++k) {
    Image image;
    image.image_id = k + 1;
    image.camera_id = k + 1;
    image.registered = true;
    image.cam_from_world = k == 0 ? Rigid3d() : pose;
    for (size_t i = 0; i < x1.size(); ++i) image.points2D.push_back({k == 0 ? x1[i] : x2[i]});
    rec.AddImage(image);
  }
  const Matrix34d P1 = Rigid3d().ToMatrix(), P2 = pose.ToMatrix();
  std::vector<point3D_t> point_ids(x1.size(), kInvalidPoint3DId);
  for (size_t i = 0; i < x1.size(); ++i) {
    Eigen::Vector3d X;
    if (!TriangulatePoint(P1, P2, n1[i], n2[i], &X)) continue;
    if (!HasPositiveDepth(Rigid3d(), X) || !HasPositiveDepth(pose, X)) continue;
    point_ids[i] = rec.AddPoint3D(X, {{1, static_cast<point2D_t>(i)}, {2, static_cast<point2D_t>(i)}});
  }
  BundleAdjustmentOptions ba;
  ba.num_threads = o.num_threads;
  ba.intrinsics.refine_focal = !result.degenerate;
  ba.intrinsics.refine_k1 = ba.intrinsics.refine_k2 = o.refine_distortion;
  // Two passes: the second after dropping the observations the first could not explain.
  for (int pass = 0; pass < 2; ++pass) {
    if (!RunBundleAdjustment(ba, BundleAdjustmentConfig::Global(rec), &rec).success) return result;
    rec.FilterObservationsWithLargeError(o.max_reprojection_error_px);
  }
  rec.FilterPointsWithSmallTriangulationAngle(o.min_triangulation_angle_deg);

  result.camera1 = rec.camera(1);
  result.camera2 = rec.camera(2);
  // Fix the scale: |t| = 1 (the points follow).
  Rigid3d pose2 = rec.image(2).cam_from_world;
  const Rigid3d pose1 = rec.image(1).cam_from_world;  // held as the gauge, stays identity
  const double scale = 1.0 / pose2.translation.norm();
  pose2.translation *= scale;
  result.cam2_from_cam1 = pose2 * pose1.Inverse();
  result.points.assign(x1.size(), Eigen::Vector3d::Zero());
  result.point_valid.assign(x1.size(), 0);
  double sum_sq = 0;
  size_t n = 0;
  for (size_t i = 0; i < x1.size(); ++i) {
    if (point_ids[i] == kInvalidPoint3DId || !rec.ExistsPoint3D(point_ids[i])) continue;
    const Point3D& point = rec.point3D(point_ids[i]);
    if (point.track.size() != 2) continue;
    result.points[i] = scale * (pose1 * point.xyz);
    result.point_valid[i] = 1;
    for (const auto& el : point.track) sum_sq += rec.SquaredReprojectionError(el, point.xyz);
    n += 2;
  }
  result.rms_px = n ? std::sqrt(sum_sq / n) : 0.0;
  result.success = n >= 16;
  return result;
}

}  // namespace varsfm
