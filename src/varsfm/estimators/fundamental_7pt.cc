#include "varsfm/estimators/fundamental_7pt.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/QR>

#include "varsfm/estimators/normalization.h"
#include "varsfm/estimators/null_vector.h"
#include "varsfm/estimators/polynomial.h"

namespace varsfm {
namespace {

// adj(M) for 3x3 M: its rows are the cross products of M's columns (adj(M) M = det(M) I).
Eigen::Matrix3d Adjugate(const Eigen::Matrix3d& M) {
  Eigen::Matrix3d adj;
  adj.row(0) = M.col(1).cross(M.col(2)).transpose();
  adj.row(1) = M.col(2).cross(M.col(0)).transpose();
  adj.row(2) = M.col(0).cross(M.col(1)).transpose();
  return adj;
}

}  // namespace

int Fundamental7pt(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                   std::vector<Eigen::Matrix3d>* models) {
  if (x1.size() < 7 || x2.size() < 7) return 0;
  const std::vector<Eigen::Vector2d> p1(x1.begin(), x1.begin() + 7), p2(x2.begin(), x2.begin() + 7);
  const NormalizedCorrespondences n = NormalizeCorrespondences(p1, p2);

  // Rows of A f = 0 with f = F in row-major order, one per constraint x2^T F x1 = 0; stored
  // transposed so the null space is the last two columns of the full Q of A^T's QR.
  Eigen::Matrix<double, 9, 7> At;
  for (int i = 0; i < 7; ++i) {
    const double u1 = n.x1[i].x(), v1 = n.x1[i].y(), u2 = n.x2[i].x(), v2 = n.x2[i].y();
    At.col(i) << u2 * u1, u2 * v1, u2, v2 * u1, v2 * v1, v2, u1, v1, 1;
  }
  const Eigen::Matrix<double, 9, 9> Q =
      Eigen::HouseholderQR<Eigen::Matrix<double, 9, 7>>(At).householderQ();
  const Eigen::Matrix3d F1 = MatrixFromRowMajor(Q.col(7));
  const Eigen::Matrix3d F2 = MatrixFromRowMajor(Q.col(8));

  // det(A + a B) = det A + a tr(adj(A) B) + a^2 tr(adj(B) A) + a^3 det B with A = F2,
  // B = F1 - F2, i.e. F = a F1 + (1 - a) F2.
  const Eigen::Matrix3d A = F2, B = F1 - F2;
  const double c0 = A.determinant();
  const double c1 = (Adjugate(A) * B).trace();
  const double c2 = (Adjugate(B) * A).trace();
  const double c3 = B.determinant();
  std::vector<double> roots;
  SolveCubicReal(c3, c2, c1, c0, &roots);
  int added = 0;
  for (const double a : roots) {
    const Eigen::Matrix3d Fn = A + a * B;
    Eigen::Matrix3d F = n.T2.transpose() * Fn * n.T1;  // undo the normalisation: x'^T T2^T Fn T1 x
    if (!ScaleToUnitNorm(&F)) continue;
    models->push_back(F);
    ++added;
  }
  return added;
}

}  // namespace varsfm
