#pragma once
// The camera of one image, with its own intrinsics (paper section 3): the calibration matrix
//   K = [ f   s   u0 ]
//       [ 0  e*f  v0 ]      (f focal length in pixels, e aspect ratio, s skew,
//       [ 0   0    1 ]       (u0, v0) principal point)
// and radial distortion applied to normalised coordinates (section 3.2, eq. 5):
//   (xd, yd) = (1 + k1 r^2 + k2 r^4) (xn, yn),  r^2 = xn^2 + yn^2,  u = K (xd, yd, 1).
// The parameters form one contiguous block so bundle adjustment can optimise them in place.
#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "varsfm/util/types.h"

namespace varsfm {

struct Camera {
  enum Param { kFocal = 0, kAspect, kSkew, kU0, kV0, kK1, kK2, kNumParams };

  // A camera with the principal point at the image centre, aspect 1, no skew or distortion.
  static Camera FromFocal(int width, int height, double focal);

  double& focal() { return params[kFocal]; }
  double focal() const { return params[kFocal]; }
  double fy() const { return params[kAspect] * params[kFocal]; }

  // The camera of the image resized to new_width x new_height: with the pixel-corner origin,
  // scaling pixel coordinates is exact (x' = sx x, y' = sy y); distortion, in normalised
  // coordinates, is unchanged.
  Camera Resized(int new_width, int new_height) const;

  Eigen::Matrix3d K() const;
  void SetK(const Eigen::Matrix3d& K);  // K(2,2) must be 1; distortion untouched

  // Camera coordinates (z > 0) -> pixel.
  Eigen::Vector2d Project(const Eigen::Vector3d& point_in_camera) const;
  // Normalised undistorted (x/z, y/z) -> pixel.
  Eigen::Vector2d NormalizedToImage(const Eigen::Vector2d& normalized) const;
  // Pixel -> normalised undistorted coordinates (distortion inverted by Newton iterations).
  Eigen::Vector2d ImageToNormalized(const Eigen::Vector2d& pixel) const;
  // A pixel threshold expressed in normalised units (for thresholds on normalised data).
  double ImageToNormalizedThreshold(double pixels) const { return pixels / params[kFocal]; }
  bool HasDistortion() const { return params[kK1] != 0.0 || params[kK2] != 0.0; }
  // The principal point's offset from the image centre (px).
  Eigen::Vector2d PrincipalPointOffset() const {
    return {params[kU0] - 0.5 * width, params[kV0] - 0.5 * height};
  }

  camera_t camera_id = 0;
  int width = 0;
  int height = 0;
  std::array<double, kNumParams> params = {1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0};
};

// Radial distortion of eq. (5), templated for Ceres automatic differentiation.
template <typename T>
void ApplyRadialDistortion(const T* params, const T& xn, const T& yn, T* xd, T* yd) {
  const T r2 = xn * xn + yn * yn;
  const T factor = T(1) + r2 * (params[Camera::kK1] + params[Camera::kK2] * r2);
  *xd = factor * xn;
  *yd = factor * yn;
}

// Camera coordinates -> pixel through the full model; templated for Ceres.
template <typename T>
void ProjectToImage(const T* params, const T* point_in_camera, T* pixel) {
  const T xn = point_in_camera[0] / point_in_camera[2];
  const T yn = point_in_camera[1] / point_in_camera[2];
  T xd, yd;
  ApplyRadialDistortion(params, xn, yn, &xd, &yd);
  const T& f = params[Camera::kFocal];
  pixel[0] = f * xd + params[Camera::kSkew] * yd + params[Camera::kU0];
  pixel[1] = params[Camera::kAspect] * f * yd + params[Camera::kV0];
}

}  // namespace varsfm
