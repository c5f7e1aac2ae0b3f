#include "varsfm/estimators/fundamental_8pt.h"

#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "varsfm/estimators/normalization.h"

namespace varsfm {

bool Fundamental8pt(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                    Eigen::Matrix3d* F) {
  if (x1.size() < 8 || x1.size() != x2.size()) return false;
  std::vector<Eigen::Vector2d> n1, n2;
  Eigen::Matrix3d T1, T2;
  NormalizePoints2D(x1, &n1, &T1);
  NormalizePoints2D(x2, &n2, &T2);
  // The least-squares f minimising |A f| is the eigenvector of A^T A with the smallest
  // eigenvalue; accumulating the 9x9 A^T A keeps the cost linear in the number of points, and
  // the normalisation keeps A^T A well conditioned.
  Eigen::Matrix<double, 9, 9> AtA = Eigen::Matrix<double, 9, 9>::Zero();
  for (size_t i = 0; i < n1.size(); ++i) {
    const double u1 = n1[i].x(), v1 = n1[i].y(), u2 = n2[i].x(), v2 = n2[i].y();
    Eigen::Matrix<double, 9, 1> a;
    a << u2 * u1, u2 * v1, u2, v2 * u1, v2 * v1, v2, u1, v1, 1;
    AtA.selfadjointView<Eigen::Lower>().rankUpdate(a);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(
      AtA.selfadjointView<Eigen::Lower>());
  if (eig.info() != Eigen::Success) return false;
  const Eigen::Matrix<double, 9, 1> f = eig.eigenvectors().col(0);
  const Eigen::Matrix3d Fn =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(f.data());
  // Rank 2 by zeroing the smallest singular value (H&Z section 11.1.1).
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(Fn, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d s = svd.singularValues();
  s[2] = 0;
  const Eigen::Matrix3d F_rank2 = svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
  const Eigen::Matrix3d result = T2.transpose() * F_rank2 * T1;
  const double norm = result.norm();
  if (!(norm > 0) || !std::isfinite(norm)) return false;
  *F = result / norm;
  return true;
}

}  // namespace varsfm
