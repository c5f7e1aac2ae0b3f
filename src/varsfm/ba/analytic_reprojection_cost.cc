#include "varsfm/ba/analytic_reprojection_cost.h"

namespace varsfm {
namespace {

// A Jacobian's destination: two rows `stride` apart (the block may hold more parameters than
// the ones written), or none.
struct JacobianOut {
  double* data = nullptr;
  int stride = 0;
  explicit operator bool() const { return data != nullptr; }
  template <int Cols>
  Eigen::Map<Eigen::Matrix<double, 2, Cols, Eigen::RowMajor>, 0, Eigen::OuterStride<>> Map() const {
    return {data, 2, Cols, Eigen::OuterStride<>(stride)};
  }
};

// Residual and the Jacobians the caller asks for; the derivation is in
// analytic_reprojection_cost.h. Returns false when the point is in the camera's plane.
bool EvaluateReprojection(const double* camera, const double* rotation, const double* translation,
                          const double* point, const Eigen::Vector2d& observed, double* residuals,
                          JacobianOut d_camera, JacobianOut d_rotation, JacobianOut d_translation,
                          JacobianOut d_point) {
  const Eigen::Vector3d v(rotation[0], rotation[1], rotation[2]);
  const double w = rotation[3];
  const Eigen::Map<const Eigen::Vector3d> X(point);
  const Eigen::Vector3d vxX = v.cross(X);
  const Eigen::Vector3d p =
      X + 2.0 * w * vxX + 2.0 * v.cross(vxX) + Eigen::Map<const Eigen::Vector3d>(translation);
  if (p.z() == 0.0) return false;

  const double inv_z = 1.0 / p.z();
  const double nx = p.x() * inv_z, ny = p.y() * inv_z;
  const double f = camera[Camera::kFocal], e = camera[Camera::kAspect], s = camera[Camera::kSkew],
               k1 = camera[Camera::kK1], k2 = camera[Camera::kK2];
  const double r2 = nx * nx + ny * ny;
  const double d = 1.0 + r2 * (k1 + k2 * r2);
  const double mx = d * nx, my = d * ny;
  residuals[0] = f * mx + s * my + camera[Camera::kU0] - observed.x();
  residuals[1] = e * f * my + camera[Camera::kV0] - observed.y();

  if (d_camera) {
    const double a = (f * nx + s * ny) * r2;
    const double b = e * f * ny * r2;
    d_camera.Map<Camera::kNumParams>() << mx, 0.0, my, 1.0, 0.0, a, a * r2,  //
        e * my, f * my, 0.0, 0.0, 1.0, b, b * r2;
  }
  if (!d_rotation && !d_translation && !d_point) return true;

  // d(u, v)/dp = A B C.
  const double g = 2.0 * (k1 + 2.0 * k2 * r2);
  Eigen::Matrix2d B;
  B << d + g * nx * nx, g * nx * ny,  //
      g * nx * ny, d + g * ny * ny;
  Eigen::Matrix2d A;
  A << f, s,  //
      0.0, e * f;
  Eigen::Matrix<double, 2, 3> C;
  C << inv_z, 0.0, -nx * inv_z,  //
      0.0, inv_z, -ny * inv_z;
  const Eigen::Matrix<double, 2, 3> J_p = A * B * C;

  if (d_translation) d_translation.Map<3>() = J_p;
  if (d_point) {
    // dp/dX = R(q), built from the same unit-quaternion formula.
    const Eigen::Quaterniond q(w, v.x(), v.y(), v.z());
    d_point.Map<3>() = J_p * q.toRotationMatrix();
  }
  if (d_rotation) {
    Eigen::Matrix3d X_cross;
    X_cross << 0.0, -X.z(), X.y(),  //
        X.z(), 0.0, -X.x(),         //
        -X.y(), X.x(), 0.0;
    Eigen::Matrix<double, 3, 4> dp_dq;
    dp_dq.leftCols<3>() = -2.0 * w * X_cross + 2.0 * (v.dot(X) * Eigen::Matrix3d::Identity() +
                                                      v * X.transpose() - 2.0 * X * v.transpose());
    dp_dq.col(3) = 2.0 * vxX;
    d_rotation.Map<4>() = J_p * dp_dq;
  }
  return true;
}

// The pose as [q, t] (p = R X + t) or, with `centre`, [q, C] (p = R (X - C), so d/dC = -d/dX).
bool EvaluateWithPose(const double* camera, const double* rotation, const double* position,
                      bool centre, const double* point, const Eigen::Vector2d& observed,
                      double* residuals, JacobianOut d_camera, JacobianOut d_rotation,
                      JacobianOut d_position, JacobianOut d_point) {
  if (!centre)
    return EvaluateReprojection(camera, rotation, position, point, observed, residuals, d_camera,
                                d_rotation, d_position, d_point);
  const double relative[3] = {point[0] - position[0], point[1] - position[1],
                              point[2] - position[2]};
  static constexpr double kZero[3] = {0.0, 0.0, 0.0};
  Eigen::Matrix<double, 2, 3, Eigen::RowMajor> d_relative;
  const bool want_relative = d_point || d_position;
  if (!EvaluateReprojection(camera, rotation, kZero, relative, observed, residuals, d_camera,
                            d_rotation, JacobianOut{},
                            JacobianOut{want_relative ? d_relative.data() : nullptr, 3}))
    return false;
  if (d_point) d_point.Map<3>() = d_relative;
  if (d_position) d_position.Map<3>() = -d_relative;
  return true;
}

}  // namespace

AnalyticReprojectionCost::AnalyticReprojectionCost(const Eigen::Vector2d& observed,
                                                   ReprojectionBlocks blocks,
                                                   std::optional<unsigned> shared_mask)
    : observed_(observed), blocks_(blocks), shared_mask_(shared_mask) {
  set_num_residuals(2);
  auto* sizes = mutable_parameter_block_sizes();
  sizes->reserve(4);  // one allocation per residual: a global adjustment builds millions
  sizes->push_back(blocks == ReprojectionBlocks::kImage ? Camera::kNumParams + 7
                                                        : Camera::kNumParams);
  if (shared_mask) sizes->push_back(Camera::kNumParams);
  if (blocks == ReprojectionBlocks::kCameraRotationTranslation) {
    sizes->push_back(4);
    sizes->push_back(3);
  } else if (blocks == ReprojectionBlocks::kCameraPose) {
    sizes->push_back(7);
  }
  sizes->push_back(3);
}

bool AnalyticReprojectionCost::Evaluate(double const* const* parameters, double* residuals,
                                        double** jacobians) const {
  const auto J = [jacobians](int i, int stride) {
    return JacobianOut{jacobians ? jacobians[i] : nullptr, stride};
  };
  // Where each parameter and its Jacobian are, by layout.
  int b = 0;
  const double* own = parameters[b];
  const int own_size =
      blocks_ == ReprojectionBlocks::kImage ? Camera::kNumParams + 7 : Camera::kNumParams;
  const JacobianOut d_own = J(b++, own_size);
  const double* group = nullptr;
  JacobianOut d_group;
  if (shared_mask_) {
    group = parameters[b];
    d_group = J(b++, Camera::kNumParams);
  }
  const double *rotation = nullptr, *translation = nullptr;
  JacobianOut d_rotation, d_translation;
  switch (blocks_) {
    case ReprojectionBlocks::kCameraRotationTranslation:
      rotation = parameters[b];
      d_rotation = J(b++, 4);
      translation = parameters[b];
      d_translation = J(b++, 3);
      break;
    case ReprojectionBlocks::kCameraPose:
      rotation = parameters[b];
      translation = rotation + 4;
      d_rotation = J(b++, 7);
      break;
    case ReprojectionBlocks::kImage:
      rotation = own + Camera::kNumParams;
      translation = rotation + 4;
      d_rotation = JacobianOut{d_own.data ? d_own.data + Camera::kNumParams : nullptr, own_size};
      break;
  }
  if (blocks_ != ReprojectionBlocks::kCameraRotationTranslation && d_rotation)
    d_translation = JacobianOut{d_rotation.data + 4, d_rotation.stride};
  const double* point = parameters[b];
  const JacobianOut d_point = J(b, 3);
  const bool centre = blocks_ != ReprojectionBlocks::kCameraRotationTranslation;

  if (!shared_mask_)
    return EvaluateWithPose(own, rotation, translation, centre, point, observed_, residuals, d_own,
                            d_rotation, d_translation, d_point);

  const unsigned mask = *shared_mask_;
  double camera[Camera::kNumParams];
  for (int i = 0; i < Camera::kNumParams; ++i) camera[i] = (mask >> i) & 1u ? group[i] : own[i];
  Eigen::Matrix<double, 2, Camera::kNumParams, Eigen::RowMajor> d_camera;
  const bool want_camera = d_own || d_group;
  if (!EvaluateWithPose(camera, rotation, translation, centre, point, observed_, residuals,
                        JacobianOut{want_camera ? d_camera.data() : nullptr, Camera::kNumParams},
                        d_rotation, d_translation, d_point))
    return false;
  // Each column of the camera Jacobian goes to the block the parameter comes from; the other
  // block's column is zero.
  for (const auto& [out, from_group] : {std::pair{d_own, false}, std::pair{d_group, true}}) {
    if (!out) continue;
    auto block = out.Map<Camera::kNumParams>();
    for (int i = 0; i < Camera::kNumParams; ++i) {
      if ((((mask >> i) & 1u) != 0) == from_group)
        block.col(i) = d_camera.col(i);
      else
        block.col(i).setZero();
    }
  }
  return true;
}

}  // namespace varsfm
