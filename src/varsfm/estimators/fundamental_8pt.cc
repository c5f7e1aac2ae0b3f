#include "varsfm/estimators/fundamental_8pt.h"

#include <Eigen/SVD>

#include "varsfm/estimators/normalization.h"
#include "varsfm/estimators/null_vector.h"

namespace varsfm {

bool Fundamental8pt(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                    Eigen::Matrix3d* F) {
  if (x1.size() < 8 || x1.size() != x2.size()) return false;
  const NormalizedCorrespondences n = NormalizeCorrespondences(x1, x2);
  // One row of x2^T F x1 = 0 per correspondence (H&Z section 11.1), f = F row-major; f is the
  // least-squares null vector (null_vector.h).
  const auto rows = [&n](size_t i, const auto& add) {
    const double u1 = n.x1[i].x(), v1 = n.x1[i].y(), u2 = n.x2[i].x(), v2 = n.x2[i].y();
    Eigen::Matrix<double, 9, 1> a;
    a << u2 * u1, u2 * v1, u2, v2 * u1, v2 * v1, v2, u1, v1, 1;
    add(a);
  };
  Eigen::Matrix<double, 9, 1> f;
  if (!NullVectorOfRows<9>(n.x1.size(), rows, &f)) return false;
  const Eigen::Matrix3d Fn = MatrixFromRowMajor(f);
  // Rank 2 by zeroing the smallest singular value (H&Z section 11.1.1).
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(Fn, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d s = svd.singularValues();
  s[2] = 0;
  const Eigen::Matrix3d F_rank2 = svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
  Eigen::Matrix3d result = n.T2.transpose() * F_rank2 * n.T1;
  if (!ScaleToUnitNorm(&result)) return false;
  *F = result;
  return true;
}

}  // namespace varsfm
