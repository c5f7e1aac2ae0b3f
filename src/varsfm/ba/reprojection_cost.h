#pragma once
// The reprojection residual of eq. (34) of El Hazzat et al.: the pixel observation minus the
// projection of a 3D point through the image's pose and its camera (per-image intrinsics with
// radial distortion, camera.h). Written as a Ceres automatic-differentiation functor, as in
// Ceres' bundle-adjustment example.
//
// Parameter blocks: camera params [f, aspect, skew, u0, v0, k1, k2] (7), cam_from_world rotation
// as an Eigen quaternion [x, y, z, w] (4, on ceres::EigenQuaternionManifold), cam_from_world
// translation (3), and the point in world coordinates (3). The rotation and translation blocks
// alias Rigid3d's storage, so the reconstruction is optimised in place.
#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "varsfm/camera/camera.h"

namespace varsfm {

class ReprojectionCost {
 public:
  explicit ReprojectionCost(const Eigen::Vector2d& observed) : observed_(observed) {}

  template <typename T>
  bool operator()(const T* camera, const T* rotation, const T* translation, const T* point,
                  T* residuals) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> x(point);
    const Eigen::Matrix<T, 3, 1> x_cam = q * x + t;  // x_cam = R x_world + t
    T pixel[2];
    ProjectToImage(camera, x_cam.data(), pixel);
    residuals[0] = pixel[0] - T(observed_.x());
    residuals[1] = pixel[1] - T(observed_.y());
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& observed) {
    return new ceres::AutoDiffCostFunction<ReprojectionCost, 2, Camera::kNumParams, 4, 3, 3>(
        new ReprojectionCost(observed));
  }

 private:
  Eigen::Vector2d observed_;
};

// The same residual with some camera parameters taken from a block shared by several cameras
// (IntrinsicsOptions::shared_per_size): parameter i comes from `group` when bit i of
// `shared_mask` is set, else from the image's own `camera` block.
class SharedIntrinsicsReprojectionCost {
 public:
  SharedIntrinsicsReprojectionCost(const Eigen::Vector2d& observed, unsigned shared_mask)
      : cost_(observed), shared_mask_(shared_mask) {}

  template <typename T>
  bool operator()(const T* camera, const T* group, const T* rotation, const T* translation,
                  const T* point, T* residuals) const {
    T params[Camera::kNumParams];
    for (int i = 0; i < Camera::kNumParams; ++i)
      params[i] = (shared_mask_ >> i) & 1u ? group[i] : camera[i];
    return cost_(params, rotation, translation, point, residuals);
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& observed, unsigned shared_mask) {
    return new ceres::AutoDiffCostFunction<SharedIntrinsicsReprojectionCost, 2, Camera::kNumParams,
                                           Camera::kNumParams, 4, 3, 3>(
        new SharedIntrinsicsReprojectionCost(observed, shared_mask));
  }

 private:
  ReprojectionCost cost_;
  unsigned shared_mask_;
};

}  // namespace varsfm
