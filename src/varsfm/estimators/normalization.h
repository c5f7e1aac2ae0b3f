#pragma once
// Hartley's isotropic normalisation (Hartley 1997, "In defense of the eight-point algorithm";
// H&Z section 4.4.4): translate the centroid to the origin and scale the mean distance to
// sqrt(2) (2D) or sqrt(3) (3D), which makes linear solvers well conditioned.
#include <vector>

#include <Eigen/Core>

namespace varsfm {

// normalized[i] = T * points[i] (homogeneous), T a similarity.
void NormalizePoints2D(const std::vector<Eigen::Vector2d>& points,
                       std::vector<Eigen::Vector2d>* normalized, Eigen::Matrix3d* T);
void NormalizePoints3D(const std::vector<Eigen::Vector3d>& points,
                       std::vector<Eigen::Vector3d>* normalized, Eigen::Matrix4d* T);

// Both sides of a set of correspondences x1[i] <-> x2[i], each normalised on its own:
// x1[i] = T1 * original x1[i], x2[i] = T2 * original x2[i].
struct NormalizedCorrespondences {
  std::vector<Eigen::Vector2d> x1, x2;
  Eigen::Matrix3d T1, T2;
};
NormalizedCorrespondences NormalizeCorrespondences(const std::vector<Eigen::Vector2d>& x1,
                                                   const std::vector<Eigen::Vector2d>& x2);

}  // namespace varsfm
