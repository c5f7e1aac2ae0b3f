#include "varsfm/estimators/projection_dlt.h"

#include <cmath>

#include <Eigen/LU>

#include "varsfm/estimators/normalization.h"
#include "varsfm/estimators/null_vector.h"

namespace varsfm {

bool ProjectionDLT(const std::vector<Eigen::Vector2d>& points2D,
                   const std::vector<Eigen::Vector3d>& points3D, Matrix34d* P) {
  if (points2D.size() < 6 || points2D.size() != points3D.size()) return false;
  std::vector<Eigen::Vector2d> n2;
  std::vector<Eigen::Vector3d> n3;
  Eigen::Matrix3d T;
  Eigen::Matrix4d U;
  NormalizePoints2D(points2D, &n2, &T);
  NormalizePoints3D(points3D, &n3, &U);
  // H&Z eq. 7.2: [X^T 0 -x X^T; 0 X^T -y X^T] p = 0, p = P row-major.
  const auto rows = [&n2, &n3](size_t i, const auto& add) {
    const Eigen::Vector4d X = n3[i].homogeneous();
    Eigen::Matrix<double, 12, 1> a, b;
    a << X, Eigen::Vector4d::Zero(), -n2[i].x() * X;
    b << Eigen::Vector4d::Zero(), X, -n2[i].y() * X;
    add(a);
    add(b);
  };
  Eigen::Matrix<double, 12, 1> p;
  if (!NullVectorOfRows<12>(n2.size(), rows, &p)) return false;
  const Matrix34d Pn = Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(p.data());
  // Undo the normalisations: T x ~ Pn U X, so P = T^-1 Pn U.
  Matrix34d result = T.inverse() * Pn * U;
  const double det = result.leftCols<3>().determinant();
  const double m3 = result.block<1, 3>(2, 0).norm();
  if (!(m3 > 0) || !std::isfinite(det) || det == 0) return false;
  result /= (det > 0 ? m3 : -m3);
  *P = result;
  return true;
}

}  // namespace varsfm
