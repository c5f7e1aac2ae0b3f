#include "varsfm/geometry/projection_decomposition.h"

#include <cmath>

#include <Eigen/LU>
#include <Eigen/QR>

namespace varsfm {

bool RQDecomposition(const Eigen::Matrix3d& M, Eigen::Matrix3d* K, Eigen::Matrix3d* R) {
  if (!std::isfinite(M.sum()) || std::abs(M.determinant()) <= 1e-300) return false;
  // RQ from QR: with J the row-reversing permutation, (J M)^T = Q' R' gives
  // M = (J R'^T J) (J Q'^T), where J R'^T J is upper triangular and J Q'^T orthonormal.
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
  J(0, 2) = J(1, 1) = J(2, 0) = 1.0;
  const Eigen::HouseholderQR<Eigen::Matrix3d> qr((J * M).transpose());
  const Eigen::Matrix3d Qp = qr.householderQ();
  const Eigen::Matrix3d Rp = qr.matrixQR().triangularView<Eigen::Upper>();
  Eigen::Matrix3d k = J * Rp.transpose() * J;
  Eigen::Matrix3d r = J * Qp.transpose();
  // The decomposition is unique up to the signs of K's columns / R's rows: D K D R with
  // D = diag(+-1). Choose D so that K has a positive diagonal.
  for (int i = 0; i < 3; ++i) {
    if (k(i, i) < 0) {
      k.col(i) *= -1.0;
      r.row(i) *= -1.0;
    }
  }
  *K = k;
  *R = r;
  return true;
}

bool DecomposeProjectionMatrix(const Matrix34d& P, Eigen::Matrix3d* K, Eigen::Matrix3d* R,
                               Eigen::Vector3d* t) {
  Matrix34d p = P;
  if (p.leftCols<3>().determinant() < 0) p = -p;
  Eigen::Matrix3d k, r;
  if (!RQDecomposition(p.leftCols<3>(), &k, &r)) return false;
  // p = lambda K [R | t] with lambda = k(2,2) > 0, so t = (lambda K)^-1 p4.
  *t = k.triangularView<Eigen::Upper>().solve(p.col(3));
  *K = k / k(2, 2);
  *R = r;
  return true;
}

}  // namespace varsfm
