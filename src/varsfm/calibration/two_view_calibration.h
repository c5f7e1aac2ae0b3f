#pragma once
// Two-view self-calibration (El Hazzat et al., section 4.2, as varsfm implements it; see
// docs/self_calibration.md for why the paper's linear system is not used): Bougnoux's focal
// lengths from F with the principal points at the image centres, aspect 1 and skew 0;
// degeneracy detection with a prior-focal fallback; then E = K2^T F K1, the pose by
// cheirality, triangulation (4.2.3) and the two-view bundle adjustment of eq. (34).
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"

namespace varsfm {

struct TwoViewCalibrationOptions {
  // A focal length outside [min, max] x max(w, h) is taken as a failure of the closed form.
  double min_focal_factor = 0.3;
  double max_focal_factor = 5.0;
  // Fallback focal length when the configuration is degenerate: the prior if given (EXIF),
  // otherwise prior_focal_factor x max(w, h) (COLMAP's default guess).
  double prior_focal_factor = 1.2;
  std::optional<double> prior_focal1, prior_focal2;
  // Sensitivity test: the focal lengths are recomputed with the principal points moved by
  // this fraction of the image size; a relative change above max_focal_sensitivity (a large
  // uncertainty of log f) marks the configuration as degenerate.
  double principal_point_perturbation = 0.02;
  double max_focal_sensitivity = 0.15;
  bool refine_distortion = true;  // k1, k2 in the two-view bundle adjustment
  double max_reprojection_error_px = 4.0;
  double min_triangulation_angle_deg = 1.0;
  int num_threads = 1;
};

struct TwoViewCalibration {
  bool success = false;
  bool degenerate = false;
  std::string degeneracy_reason;
  Camera camera1, camera2;
  Rigid3d cam2_from_cam1;                 // |t| = 1
  std::vector<Eigen::Vector3d> points;    // one per correspondence, in camera 1's frame
  std::vector<char> point_valid;          // in front of both, small error, enough angle
  double rms_px = 0;                      // over the valid points after refinement
};

// Bougnoux's focal lengths (principal points at the centres) when they can be trusted: positive,
// in the plausible range and insensitive to the principal points; otherwise nullopt and the
// reason. Cheap: the mapper uses it to rank initial pairs before calibrating one.
std::optional<std::pair<double, double>> ClosedFormFocalLengths(
    const Eigen::Matrix3d& F, int width1, int height1, int width2, int height2,
    const TwoViewCalibrationOptions& options, std::string* reason);

// x1, x2: inlier correspondences (pixels) of a fundamental matrix F (x2^T F x1 = 0).
TwoViewCalibration CalibrateTwoView(const std::vector<Eigen::Vector2d>& x1,
                                    const std::vector<Eigen::Vector2d>& x2, int width1,
                                    int height1, int width2, int height2,
                                    const Eigen::Matrix3d& F,
                                    const TwoViewCalibrationOptions& options);

}  // namespace varsfm
