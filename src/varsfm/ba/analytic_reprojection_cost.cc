#include "varsfm/ba/analytic_reprojection_cost.h"

namespace varsfm {
namespace {

using RowMajor2x3 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
using RowMajor2x4 = Eigen::Matrix<double, 2, 4, Eigen::RowMajor>;
using RowMajor2x7 = Eigen::Matrix<double, 2, Camera::kNumParams, Eigen::RowMajor>;

// Residual and the Jacobians the caller asks for (null pointers are skipped); the derivation is
// in analytic_reprojection_cost.h. Returns false behind the camera (no valid projection).
bool EvaluateReprojection(const double* camera, const double* rotation, const double* translation,
                          const double* point, const Eigen::Vector2d& observed, double* residuals,
                          double* d_camera, double* d_rotation, double* d_translation,
                          double* d_point) {
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
    Eigen::Map<RowMajor2x7> J(d_camera);
    J << mx, 0.0, my, 1.0, 0.0, a, a * r2,  //
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

  if (d_translation) Eigen::Map<RowMajor2x3>{d_translation} = J_p;
  if (d_point) {
    // dp/dX = R(q), built from the same unit-quaternion formula.
    const Eigen::Quaterniond q(w, v.x(), v.y(), v.z());
    Eigen::Map<RowMajor2x3>{d_point} = J_p * q.toRotationMatrix();
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
    Eigen::Map<RowMajor2x4>{d_rotation} = J_p * dp_dq;
  }
  return true;
}

}  // namespace

bool AnalyticReprojectionCost::Evaluate(double const* const* parameters, double* residuals,
                                        double** jacobians) const {
  const auto J = [jacobians](int i) { return jacobians ? jacobians[i] : nullptr; };
  return EvaluateReprojection(parameters[0], parameters[1], parameters[2], parameters[3], observed_,
                              residuals, J(0), J(1), J(2), J(3));
}

bool AnalyticSharedIntrinsicsReprojectionCost::Evaluate(double const* const* parameters,
                                                        double* residuals,
                                                        double** jacobians) const {
  double camera[Camera::kNumParams];
  for (int i = 0; i < Camera::kNumParams; ++i)
    camera[i] = (shared_mask_ >> i) & 1u ? parameters[1][i] : parameters[0][i];
  const auto J = [jacobians](int i) { return jacobians ? jacobians[i] : nullptr; };
  const bool want_camera = J(0) || J(1);
  double d_camera[2 * Camera::kNumParams];
  if (!EvaluateReprojection(camera, parameters[2], parameters[3], parameters[4], observed_,
                            residuals, want_camera ? d_camera : nullptr, J(2), J(3), J(4)))
    return false;
  // Each column of the camera Jacobian goes to the block the parameter comes from; the other
  // block's column is zero.
  for (int block = 0; block < 2; ++block) {
    if (!J(block)) continue;
    Eigen::Map<RowMajor2x7> out(J(block));
    const Eigen::Map<const RowMajor2x7> full(d_camera);
    for (int i = 0; i < Camera::kNumParams; ++i) {
      const bool shared = (shared_mask_ >> i) & 1u;
      if (shared == (block == 1))
        out.col(i) = full.col(i);
      else
        out.col(i).setZero();
    }
  }
  return true;
}

}  // namespace varsfm
