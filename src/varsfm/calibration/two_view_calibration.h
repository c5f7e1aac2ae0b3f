#pragma once
// Two-view self-calibration (El Hazzat et al., section 4.2, replaced as docs/self_calibration.md
// explains): Bougnoux focal lengths from F with the principal points at the image centres,
// degeneracy detection with a focal prior as fallback, pose from E = K2^T F K1 with cheirality,
// linear triangulation, then joint refinement of f1, f2, (k1, k2), pose and points by two-view
// bundle adjustment (eq. 34).
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"

namespace varsfm {

struct TwoViewCalibrationOptions {
  double min_focal_factor = 0.3;  // plausible focal range, x max(w, h)
  double max_focal_factor = 5.0;
  double prior_focal_factor = 1.2;  // fallback focal x max(w, h) when no EXIF prior
  std::optional<double> prior_focal1, prior_focal2;  // EXIF focal lengths (px)
  // The principal points are (nearly) in epipolar correspondence - the optical axes (nearly)
  // meet, where Bougnoux's formula is singular - when the Sampson distance of (p1, p2) to F is
  // below this fraction of max(w, h).
  double min_principal_point_epipolar_distance = 0.01;
  // Below this median triangulation angle (degrees) the pair has too little parallax (pure
  // rotation, or too short a baseline): F, and the focal lengths from it, are meaningless.
  double min_median_triangulation_angle_deg = 1.0;
  // After the refinement: the pair is flagged degenerate when the standard deviation of log f1
  // or log f2 (focal_uncertainty.h, with the refinement's own residual as the noise level)
  // exceeds this; the refined values are kept (the caller decides whether to use the pair).
  // 0.015 measured on tests/calibration's pairs (0.5 px noise, 500 points, k1, k2 held):
  // well-determined pairs 0.004-0.011 with focal errors <= 0.85 %, the two weak ones
  // 0.021-0.030 with errors of 10-11 %.
  double max_log_focal_std = 0.015;
  bool refine_distortion = true;
  double loss_scale_px = 1.0;  // Cauchy scale of the refinement
  int num_threads = 0;         // of the refinement (bundle_adjuster.h: 0 = all cores)
};

struct TwoViewCalibration {
  bool success = false;
  bool degenerate = false;
  // Degenerate before the refinement: the focal lengths are the priors, held (the refinement
  // can flag a pair too, keeping its refined focal lengths).
  bool focal_from_prior = false;
  std::string degeneracy_reason;
  Camera camera1, camera2;
  Rigid3d cam2_from_cam1;
  std::vector<Eigen::Vector3d> points;  // in camera 1's frame, |t| = 1 before refinement
  std::vector<char> point_valid;        // in front of both cameras after refinement
  double rms_px = 0.0;                  // 2D reprojection RMS over the valid points
  // Standard deviations of log f1, log f2 after the refinement (infinity: undetermined; 0
  // when the pair was flagged degenerate before the refinement and f was held).
  double log_focal_std1 = 0.0, log_focal_std2 = 0.0;
};

// x1, x2: inlier correspondences (pixels) of F (x2^T F x1 = 0) between an image of w1 x h1 and
// one of w2 x h2 pixels.
TwoViewCalibration CalibrateTwoView(const std::vector<Eigen::Vector2d>& x1,
                                    const std::vector<Eigen::Vector2d>& x2, int w1, int h1, int w2,
                                    int h2, const Eigen::Matrix3d& F,
                                    const TwoViewCalibrationOptions& options);

}  // namespace varsfm
