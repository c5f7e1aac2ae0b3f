#include "varsfm/geometry/fundamental.h"

#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>

namespace varsfm {

Eigen::Matrix3d CrossProductMatrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

void Epipoles(const Eigen::Matrix3d& F, Eigen::Vector3d* e1, Eigen::Vector3d* e2) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  if (e1 != nullptr) *e1 = svd.matrixV().col(2);
  if (e2 != nullptr) *e2 = svd.matrixU().col(2);
}

Eigen::Vector4d ProjectionCenter(const Matrix34d& P) {
  Eigen::Vector4d C;
  for (int i = 0; i < 4; ++i) {
    Eigen::Matrix3d minor;
    for (int c = 0, k = 0; c < 4; ++c) {
      if (c != i) minor.col(k++) = P.col(c);
    }
    C[i] = ((i % 2 == 0) ? 1.0 : -1.0) * minor.determinant();
  }
  return C;
}

Eigen::Matrix3d FundamentalFromProjections(const Matrix34d& P1, const Matrix34d& P2) {
  const Eigen::Vector3d e2 = P2 * ProjectionCenter(P1);
  // P1^+ = P1^T (P1 P1^T)^-1, the right pseudo-inverse of a full-rank 3x4 matrix.
  const Eigen::Matrix<double, 4, 3> P1_pinv = P1.transpose() * (P1 * P1.transpose()).inverse();
  const Eigen::Matrix3d F = CrossProductMatrix(e2) * P2 * P1_pinv;
  return F / F.norm();
}

Eigen::Matrix3d EssentialFromPose(const Rigid3d& cam2_from_cam1) {
  return CrossProductMatrix(cam2_from_cam1.translation) * cam2_from_cam1.R();
}

Eigen::Matrix3d FundamentalFromPose(const Eigen::Matrix3d& K1, const Eigen::Matrix3d& K2,
                                    const Rigid3d& cam2_from_cam1) {
  const Eigen::Matrix3d F =
      K2.inverse().transpose() * EssentialFromPose(cam2_from_cam1) * K1.inverse();
  return F / F.norm();
}

double SampsonError(const Eigen::Matrix3d& F, const Eigen::Vector2d& x1,
                    const Eigen::Vector2d& x2) {
  return std::sqrt(SampsonErrorSquared(F, x1, x2));
}

bool SatisfiesOrientedEpipolarConstraint(const Eigen::Matrix3d& F,
                                         const std::vector<Eigen::Vector2d>& x1,
                                         const std::vector<Eigen::Vector2d>& x2) {
  // e2 spans F's left null space (F^T e2 = 0): it is orthogonal to F's columns, so the cross
  // product of two of them, the pair with the largest product for a rank-2 F that is nearly
  // rank 1 in one pair. Not Epipoles' SVD: RANSAC tests every seven-point model (exactly rank 2)
  // here, and the test needs e2's direction only, not its scale or sign.
  Eigen::Vector3d e2 = F.col(0).cross(F.col(1));
  for (const Eigen::Vector3d& c : {F.col(0).cross(F.col(2)), F.col(1).cross(F.col(2))})
    if (c.squaredNorm() > e2.squaredNorm()) e2 = c;
  double reference = 0.0;
  for (size_t i = 0; i < x1.size() && i < x2.size(); ++i) {
    const double sign = e2.cross(x2[i].homogeneous()).dot(F * x1[i].homogeneous());
    if (reference == 0.0)
      reference = sign;
    else if (reference * sign < 0.0)
      return false;
  }
  return true;
}

}  // namespace varsfm
