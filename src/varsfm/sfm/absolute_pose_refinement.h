#pragma once
// Non-linear refinement of one image's pose and free intrinsics from its 2D-3D correspondences,
// the 3D points held fixed (the step after the DLT and its decomposition in section 4.3).
// Solved by the project's bundle-adjustment solver (ba/schur_solver.h, Levenberg-Marquardt
// as Ceres', the same cost and Cauchy loss), not through a ceres::Problem: a registration
// refines two hypotheses of ~1000 correspondences, and building, evaluating and destroying a
// ceres::Problem took two thirds of the registration's time (docs/measurements.md). The minimum
// is Ceres' (tests compare them).
#include <vector>

#include <Eigen/Core>

#include "varsfm/ba/bundle_adjuster.h"
#include "varsfm/camera/camera.h"
#include "varsfm/geometry/rigid3.h"

namespace varsfm {

struct AbsolutePoseRefinementOptions {
  IntrinsicsOptions intrinsics;  // which camera parameters are refined with the pose
  double loss_scale_px = 1.0;    // Cauchy loss scale
  int max_iterations = 50;
};

// Returns false when the problem could not be solved; `camera` and `cam_from_world` are updated
// in place otherwise.
bool RefineAbsolutePose(const AbsolutePoseRefinementOptions& options,
                        const std::vector<Eigen::Vector2d>& points2D,
                        const std::vector<Eigen::Vector3d>& points3D, Camera* camera,
                        Rigid3d* cam_from_world);

}  // namespace varsfm
