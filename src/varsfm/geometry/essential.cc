#include "varsfm/geometry/essential.h"

#include <cmath>
#include <limits>

#include <Eigen/SVD>

#include "varsfm/geometry/triangulation.h"

namespace varsfm {

void DecomposeEssentialMatrix(const Eigen::Matrix3d& E, Eigen::Matrix3d* R1, Eigen::Matrix3d* R2,
                              Eigen::Vector3d* t) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(E, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  Eigen::Matrix3d V = svd.matrixV();
  // E's null vectors are defined up to sign, so U and V can be made proper rotations; then
  // U W V^T is a rotation too.
  if (U.determinant() < 0) U.col(2) *= -1;
  if (V.determinant() < 0) V.col(2) *= -1;
  Eigen::Matrix3d W;
  W << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  *R1 = U * W * V.transpose();
  *R2 = U * W.transpose() * V.transpose();
  *t = U.col(2).normalized();
}

Eigen::Matrix3d ProjectToEssential(const Eigen::Matrix3d& M) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // Equal singular values normalised so that |E|_F = 1.
  const Eigen::Vector3d s(std::sqrt(0.5), std::sqrt(0.5), 0.0);
  return svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
}

std::vector<Rigid3d> PosesFromEssentialMatrix(const Eigen::Matrix3d& E) {
  Eigen::Matrix3d R1, R2;
  Eigen::Vector3d t;
  DecomposeEssentialMatrix(E, &R1, &R2, &t);
  return {Rigid3d(R1, t), Rigid3d(R1, -t), Rigid3d(R2, t), Rigid3d(R2, -t)};
}

int PoseFromEssentialMatrix(const Eigen::Matrix3d& E, const std::vector<Eigen::Vector2d>& x1,
                            const std::vector<Eigen::Vector2d>& x2, Rigid3d* cam2_from_cam1,
                            std::vector<char>* cheirality_mask) {
  const Matrix34d P1 = Matrix34d::Identity();
  int best_count = -1;
  std::vector<char> mask(x1.size()), best_mask;
  for (const Rigid3d& pose : PosesFromEssentialMatrix(E)) {
    const Matrix34d P2 = pose.ToMatrix();
    int count = 0;
    for (size_t i = 0; i < x1.size(); ++i) {
      Eigen::Vector3d X;
      // A point at infinity (pure rotation) cannot disambiguate; it counts as not in front.
      const bool ok = TriangulatePoint(P1, P2, x1[i], x2[i], &X) && X.z() > 0 && (pose * X).z() > 0;
      mask[i] = ok;
      count += ok;
    }
    if (count > best_count) {
      best_count = count;
      best_mask = mask;
      *cam2_from_cam1 = pose;
    }
  }
  if (cheirality_mask != nullptr) *cheirality_mask = best_mask;
  return best_count;
}

}  // namespace varsfm
