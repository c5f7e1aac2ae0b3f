#pragma once
// The residual of the estimators that project 3D points (DLT projection matrix, calibrated
// absolute pose).
#include <limits>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace varsfm {

// Squared distance between the projection of `projected` (a point in the camera frame, or P X
// for a projection matrix whose third row gives the depth) and the observation; infinity for a
// point behind the camera or on its principal plane, which no threshold admits.
inline double SquaredReprojectionResidual(const Eigen::Vector3d& projected,
                                          const Eigen::Vector2d& observed) {
  if (!(projected.z() > std::numeric_limits<double>::epsilon()))
    return std::numeric_limits<double>::infinity();
  return (projected.hnormalized() - observed).squaredNorm();
}

}  // namespace varsfm
