#pragma once
// Robust calibrated absolute pose: LO-RANSAC (ransac.h) around the P3P solver (p3p.h), with a
// Gauss-Newton refinement of the pose on the inliers' reprojection errors as the non-minimal
// solver. The 2D points are normalised image coordinates (Camera::ImageToNormalized), so the
// residual and max_error are in normalised units (pixels / focal length); a point behind the
// camera is an outlier. Run it as Ransac(AbsolutePoseEstimator{points2D, points3D}, options),
// the two vectors of one size.
#include <vector>

#include <Eigen/Core>

#include "varsfm/estimators/ransac.h"
#include "varsfm/geometry/rigid3.h"

namespace varsfm {

struct AbsolutePoseEstimator {
  using Model = Rigid3d;  // cam_from_world
  static constexpr int kMinSampleSize = 3;
  const std::vector<Eigen::Vector2d>& points2D;  // normalised image coordinates
  const std::vector<Eigen::Vector3d>& points3D;
  size_t NumData() const { return points2D.size(); }
  void MinimalSolve(const std::vector<int>& sample, std::vector<Model>* models) const;
  // The pose from `initial` that minimises the squared reprojection errors of `indices`
  // (Gauss-Newton with Levenberg-Marquardt damping; a pose needs an initial value, unlike the
  // linear solvers of the other estimators).
  void NonMinimalSolve(const std::vector<int>& indices, const Model& initial,
                       std::vector<Model>* models) const;
  double SquaredResidual(const Model& pose, size_t i) const;
};

}  // namespace varsfm
