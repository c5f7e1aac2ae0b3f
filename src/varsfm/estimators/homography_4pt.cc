#include "varsfm/estimators/homography_4pt.h"

#include <cmath>

#include <Eigen/LU>

#include "varsfm/estimators/normalization.h"
#include "varsfm/estimators/null_vector.h"

namespace varsfm {

bool HomographyDLT(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                   Eigen::Matrix3d* H) {
  if (x1.size() < 4 || x1.size() != x2.size()) return false;
  const NormalizedCorrespondences n = NormalizeCorrespondences(x1, x2);
  // Two rows of x2 x (H x1) = 0 per correspondence (H&Z eq. 4.3), h = H row-major.
  const auto rows = [&n](size_t i, const auto& add) {
    const double u1 = n.x1[i].x(), v1 = n.x1[i].y(), u2 = n.x2[i].x(), v2 = n.x2[i].y();
    Eigen::Matrix<double, 9, 1> a, b;
    a << 0, 0, 0, -u1, -v1, -1, v2 * u1, v2 * v1, v2;
    b << u1, v1, 1, 0, 0, 0, -u2 * u1, -u2 * v1, -u2;
    add(a);
    add(b);
  };
  Eigen::Matrix<double, 9, 1> h;
  if (!NullVectorOfRows<9>(n.x1.size(), rows, &h)) return false;
  // x2 = T2^-1 Hn T1 x1.
  const Eigen::Matrix3d result = n.T2.inverse() * MatrixFromRowMajor(h) * n.T1;
  const double norm = result.norm();
  if (!(norm > 0) || !std::isfinite(norm) ||
      std::abs(result.determinant()) < 1e-12 * norm * norm * norm)
    return false;
  *H = result / norm;
  return true;
}

}  // namespace varsfm
