#pragma once
// A rigid transform y = R x + t. Poses are stored world-to-camera (cam_from_world), as COLMAP's
// images.txt: x_cam = R x_world + t, camera centre C = -R^T t.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace varsfm {

struct Rigid3d {
  Rigid3d() = default;
  Rigid3d(const Eigen::Quaterniond& r, const Eigen::Vector3d& t) : rotation(r), translation(t) {}
  Rigid3d(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) : rotation(R), translation(t) {}

  Eigen::Vector3d operator*(const Eigen::Vector3d& x) const { return rotation * x + translation; }
  Rigid3d Inverse() const {
    const Eigen::Quaterniond inv = rotation.inverse();
    return {inv, -(inv * translation)};
  }
  Eigen::Matrix3d R() const { return rotation.toRotationMatrix(); }
  Eigen::Matrix<double, 3, 4> ToMatrix() const {
    Eigen::Matrix<double, 3, 4> m;
    m << R(), translation;
    return m;
  }
  // The camera centre in world coordinates when this is a cam_from_world pose.
  Eigen::Vector3d Center() const { return -(rotation.inverse() * translation); }

  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
};

inline Rigid3d operator*(const Rigid3d& a, const Rigid3d& b) {
  return {(a.rotation * b.rotation).normalized(), a.rotation * b.translation + a.translation};
}

// A cam_from_world pose for a camera at `center` looking at `target`. The image y axis (rows
// grow downwards) follows `down`, projected orthogonally to the viewing direction.
inline Rigid3d LookAt(const Eigen::Vector3d& center, const Eigen::Vector3d& target,
                      const Eigen::Vector3d& down = Eigen::Vector3d::UnitY()) {
  const Eigen::Vector3d z = (target - center).normalized();
  const Eigen::Vector3d x = down.cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;  // rows: camera axes in world coordinates
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = z.transpose();
  return {R, -R * center};
}

}  // namespace varsfm
