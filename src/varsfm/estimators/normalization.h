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

}  // namespace varsfm
