#include "varsfm/camera/camera.h"

#include <cmath>

namespace varsfm {

Camera Camera::FromFocal(int width, int height, double focal) {
  Camera camera;
  camera.width = width;
  camera.height = height;
  camera.params = {focal, 1.0, 0.0, width / 2.0, height / 2.0, 0.0, 0.0};
  return camera;
}

Camera Camera::Resized(int new_width, int new_height) const {
  const double sx = static_cast<double>(new_width) / width;
  const double sy = static_cast<double>(new_height) / height;
  Camera resized = *this;
  resized.width = new_width;
  resized.height = new_height;
  resized.params[kFocal] *= sx;
  resized.params[kAspect] *= sy / sx;
  resized.params[kSkew] *= sx;
  resized.params[kU0] *= sx;
  resized.params[kV0] *= sy;
  return resized;
}

Eigen::Matrix3d Camera::K() const {
  Eigen::Matrix3d K;
  K << params[kFocal], params[kSkew], params[kU0], 0, fy(), params[kV0], 0, 0, 1;
  return K;
}

void Camera::SetK(const Eigen::Matrix3d& K) {
  params[kFocal] = K(0, 0);
  params[kAspect] = K(1, 1) / K(0, 0);
  params[kSkew] = K(0, 1);
  params[kU0] = K(0, 2);
  params[kV0] = K(1, 2);
}

Eigen::Vector2d Camera::Project(const Eigen::Vector3d& point_in_camera) const {
  Eigen::Vector2d pixel;
  ProjectToImage(params.data(), point_in_camera.data(), pixel.data());
  return pixel;
}

Eigen::Vector2d Camera::NormalizedToImage(const Eigen::Vector2d& normalized) const {
  return Project(normalized.homogeneous());
}

Eigen::Vector2d Camera::ImageToNormalized(const Eigen::Vector2d& pixel) const {
  // Invert K (upper triangular), then the radial distortion.
  const double f = params[kFocal];
  const double yd = (pixel.y() - params[kV0]) / fy();
  const double xd = (pixel.x() - params[kU0] - params[kSkew] * yd) / f;
  if (!HasDistortion()) return {xd, yd};
  // Newton's method on g(x) = x * d(|x|^2) - x_d, started at x_d; converges in a few steps
  // for the moderate distortions of real lenses.
  Eigen::Vector2d x(xd, yd);
  const Eigen::Vector2d target(xd, yd);
  const double k1 = params[kK1], k2 = params[kK2];
  for (int iter = 0; iter < 20; ++iter) {
    const double r2 = x.squaredNorm();
    const double d = 1 + k1 * r2 + k2 * r2 * r2;
    const double dd_dr2 = k1 + 2 * k2 * r2;
    const Eigen::Vector2d residual = d * x - target;
    // Jacobian of d(r2) x: d I + 2 dd/dr2 x x^T.
    const Eigen::Matrix2d J = d * Eigen::Matrix2d::Identity() + 2 * dd_dr2 * x * x.transpose();
    const Eigen::Vector2d step = J.lu().solve(residual);
    x -= step;
    if (step.squaredNorm() < 1e-24) break;
  }
  return x;
}

}  // namespace varsfm
