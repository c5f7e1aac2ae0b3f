#include "varsfm/calibration/two_view_calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "varsfm/ba/bundle_adjuster.h"
#include "varsfm/calibration/bougnoux.h"
#include "varsfm/calibration/focal_uncertainty.h"
#include "varsfm/geometry/essential.h"
#include "varsfm/geometry/fundamental.h"
#include "varsfm/geometry/triangulation.h"
#include "varsfm/scene/reconstruction.h"

namespace varsfm {
namespace {

// Fills result->degenerate / reason and returns the focal lengths to start from.
std::pair<double, double> InitialFocals(const Eigen::Matrix3d& F, const Camera& c1,
                                        const Camera& c2, const TwoViewCalibrationOptions& o,
                                        TwoViewCalibration* result) {
  const Eigen::Vector2d pp1(c1.params[Camera::kU0], c1.params[Camera::kV0]);
  const Eigen::Vector2d pp2(c2.params[Camera::kU0], c2.params[Camera::kV0]);
  const double size1 = std::max(c1.width, c1.height), size2 = std::max(c2.width, c2.height);
  const auto fallback = [&](const std::string& reason) {
    result->degenerate = true;
    result->focal_from_prior = true;
    result->degeneracy_reason = reason;
    return std::make_pair(o.prior_focal1.value_or(o.prior_focal_factor * size1),
                          o.prior_focal2.value_or(o.prior_focal_factor * size2));
  };
  // Bougnoux's f^2 are proportional to p2^T F p1: near zero the estimate is noise.
  const double pp_distance = SampsonError(F, pp1, pp2);
  if (pp_distance < o.min_principal_point_epipolar_distance * std::max(size1, size2))
    return fallback("optical axes nearly intersect (principal points in epipolar correspondence)");
  const auto focals = BougnouxFocalLengths(F, pp1, pp2);
  if (!focals) return fallback("f^2 <= 0");
  if (focals->first < o.min_focal_factor * size1 || focals->first > o.max_focal_factor * size1 ||
      focals->second < o.min_focal_factor * size2 || focals->second > o.max_focal_factor * size2)
    return fallback("focal length outside the plausible range");
  return *focals;
}

}  // namespace

TwoViewCalibration CalibrateTwoView(const std::vector<Eigen::Vector2d>& x1,
                                    const std::vector<Eigen::Vector2d>& x2, int w1, int h1, int w2,
                                    int h2, const Eigen::Matrix3d& F,
                                    const TwoViewCalibrationOptions& options) {
  TwoViewCalibration result;
  result.camera1 = Camera::FromFocal(w1, h1, 1.0);
  result.camera2 = Camera::FromFocal(w2, h2, 1.0);
  result.camera1.camera_id = 1;
  result.camera2.camera_id = 2;
  if (x1.size() != x2.size() || x1.size() < 8) return result;
  const auto [f1, f2] = InitialFocals(F, result.camera1, result.camera2, options, &result);
  result.camera1.focal() = f1;
  result.camera2.focal() = f2;

  // Pose from E = K2^T F K1 (H&Z eq. 9.12) with cheirality, linear triangulation of the
  // normalised correspondences into a two-image reconstruction; returns the median
  // triangulation angle (radians), or -1 when no pose puts points in front of both cameras.
  Reconstruction rec;
  std::vector<point3D_t> ids;
  const auto build = [&]() -> double {
    const Eigen::Matrix3d E =
        ProjectToEssential(result.camera2.K().transpose() * F * result.camera1.K());
    std::vector<Eigen::Vector2d> n1(x1.size()), n2(x2.size());
    for (size_t i = 0; i < x1.size(); ++i) {
      n1[i] = result.camera1.ImageToNormalized(x1[i]);
      n2[i] = result.camera2.ImageToNormalized(x2[i]);
    }
    if (PoseFromEssentialMatrix(E, n1, n2, &result.cam2_from_cam1) == 0) return -1.0;
    rec = Reconstruction();
    rec.AddCamera(result.camera1);
    rec.AddCamera(result.camera2);
    Image image1, image2;
    image1.image_id = image1.camera_id = 1;
    image2.image_id = image2.camera_id = 2;
    image2.cam_from_world = result.cam2_from_cam1;
    image1.registered = image2.registered = true;
    for (size_t i = 0; i < x1.size(); ++i) {
      image1.points2D.push_back({x1[i]});
      image2.points2D.push_back({x2[i]});
    }
    rec.AddImage(image1);
    rec.AddImage(image2);
    const Matrix34d P1 = Rigid3d().ToMatrix(), P2 = result.cam2_from_cam1.ToMatrix();
    const Eigen::Vector3d c2 = result.cam2_from_cam1.Center();
    ids.assign(x1.size(), kInvalidPoint3DId);
    std::vector<double> angles;
    for (size_t i = 0; i < x1.size(); ++i) {
      Eigen::Vector3d X;
      if (!TriangulatePoint(P1, P2, n1[i], n2[i], &X) || !HasPositiveDepth(Rigid3d(), X) ||
          !HasPositiveDepth(result.cam2_from_cam1, X))
        continue;
      ids[i] = rec.AddPoint3D(X, {{1, static_cast<point2D_t>(i)}, {2, static_cast<point2D_t>(i)}});
      angles.push_back(TriangulationAngle(Eigen::Vector3d::Zero(), c2, X));
    }
    if (angles.empty()) return -1.0;
    std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
    return angles[angles.size() / 2];
  };
  const double median_angle = build();
  if (median_angle >= 0.0 && !result.degenerate &&
      median_angle < options.min_median_triangulation_angle_deg * M_PI / 180.0) {
    result.degenerate = true;
    result.focal_from_prior = true;
    result.degeneracy_reason = "too little parallax (pure rotation or short baseline)";
    result.camera1.focal() =
        options.prior_focal1.value_or(options.prior_focal_factor * std::max(w1, h1));
    result.camera2.focal() =
        options.prior_focal2.value_or(options.prior_focal_factor * std::max(w2, h2));
    if (build() < 0.0) return result;
  } else if (median_angle < 0.0) {
    return result;
  }
  if (rec.points3D().size() < 8) return result;

  BundleAdjustmentOptions ba;
  ba.loss_scale_px = options.loss_scale_px;
  ba.num_threads = options.num_threads;
  // A degenerate pair cannot determine the focal lengths: hold the prior.
  ba.intrinsics.refine_focal = !result.degenerate;
  ba.intrinsics.refine_k1 = ba.intrinsics.refine_k2 = options.refine_distortion;
  const BundleAdjustmentSummary summary =
      RunBundleAdjustment(ba, BundleAdjustmentConfig::Global(rec), &rec);
  if (!summary.success) return result;
  if (!result.degenerate) {
    // Noise level: the refinement's own residual per coordinate, at least a quarter pixel.
    const double sigma = std::max(summary.final_rms_px / std::sqrt(2.0), 0.25);
    const auto stddev = TwoViewLogFocalStdDev(rec, 1, 2, sigma, options.refine_distortion);
    constexpr double kUndetermined = std::numeric_limits<double>::infinity();
    result.log_focal_std1 = stddev ? stddev->first : kUndetermined;
    result.log_focal_std2 = stddev ? stddev->second : kUndetermined;
    // Flagged, but the refined values are kept: they fit the data as well as any other in the
    // valley and are a better start than the prior for the mapper's later adjustments, which
    // prefer pairs that are not flagged (sfm/incremental_mapper.cc).
    if (std::max(result.log_focal_std1, result.log_focal_std2) > options.max_log_focal_std) {
      result.degenerate = true;
      result.degeneracy_reason =
          fmt::format("focal lengths poorly determined (std of log f {:.3f}, {:.3f})",
                      result.log_focal_std1, result.log_focal_std2);
    }
  }

  result.camera1 = rec.camera(1);
  result.camera2 = rec.camera(2);
  // Image 1 is the gauge image (held at the identity), so its frame is the world frame.
  result.cam2_from_cam1 = rec.image(2).cam_from_world;
  result.points.assign(x1.size(), Eigen::Vector3d::Zero());
  result.point_valid.assign(x1.size(), 0);
  double sum = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < x1.size(); ++i) {
    if (ids[i] == kInvalidPoint3DId) continue;
    const Eigen::Vector3d& X = rec.point3D(ids[i]).xyz;
    result.points[i] = X;
    if (!HasPositiveDepth(Rigid3d(), X) || !HasPositiveDepth(result.cam2_from_cam1, X)) continue;
    result.point_valid[i] = 1;
    for (const TrackElement& el : rec.point3D(ids[i]).track) {
      sum += rec.SquaredReprojectionError(el, X);
      ++n;
    }
  }
  result.rms_px = n ? std::sqrt(sum / n) : 0.0;
  result.success = n > 0;
  return result;
}

}  // namespace varsfm
