#include "varsfm/estimators/fundamental_8pt.h"

#include <Eigen/SVD>

#include "varsfm/estimators/normalization.h"
#include "varsfm/estimators/null_vector.h"

namespace varsfm {

bool Fundamental8pt(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                    Eigen::Matrix3d* F) {
  if (x1.size() < 8 || x1.size() != x2.size()) return false;
  const NormalizedCorrespondences n = NormalizeCorrespondences(x1, x2);
  // The least-squares f minimising |A f| is the eigenvector of A^T A with the smallest
  // eigenvalue; accumulating the 9x9 A^T A keeps the cost linear in the number of points, and
  // the normalisation keeps A^T A well conditioned.
  Eigen::Matrix<double, 9, 9> AtA = Eigen::Matrix<double, 9, 9>::Zero();
  for (size_t i = 0; i < n.x1.size(); ++i) {
    const double u1 = n.x1[i].x(), v1 = n.x1[i].y(), u2 = n.x2[i].x(), v2 = n.x2[i].y();
    Eigen::Matrix<double, 9, 1> a;
    a << u2 * u1, u2 * v1, u2, v2 * u1, v2 * v1, v2, u1, v1, 1;
    AtA.selfadjointView<Eigen::Lower>().rankUpdate(a);
  }
  Eigen::Matrix<double, 9, 1> f;
  if (!SmallestEigenvector(AtA, &f)) return false;
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
