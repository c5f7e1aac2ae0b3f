#include "varsfm/estimators/homography_4pt.h"

#include <array>
#include <cmath>

#include <Eigen/LU>

#include "varsfm/estimators/normalization.h"
#include "varsfm/estimators/null_vector.h"

namespace varsfm {
namespace {

// The two rows of x2 x (H x1) = 0 for correspondence i (H&Z eq. 4.3), h = H row-major.
void DltRows(const NormalizedCorrespondences& n, size_t i, Eigen::Matrix<double, 9, 1>* a,
             Eigen::Matrix<double, 9, 1>* b) {
  const double u1 = n.x1[i].x(), v1 = n.x1[i].y(), u2 = n.x2[i].x(), v2 = n.x2[i].y();
  *a << 0, 0, 0, -u1, -v1, -1, v2 * u1, v2 * v1, v2;
  *b << u1, v1, 1, 0, 0, 0, -u2 * u1, -u2 * v1, -u2;
}

// x2 = T2^-1 Hn T1 x1, scaled to unit norm; false when it is (nearly) singular.
bool Denormalize(const NormalizedCorrespondences& n, const Eigen::Matrix3d& Hn,
                 Eigen::Matrix3d* H) {
  const Eigen::Matrix3d result = n.T2.inverse() * Hn * n.T1;
  const double norm = result.norm();
  if (!(norm > 0) || !std::isfinite(norm) ||
      std::abs(result.determinant()) < 1e-12 * norm * norm * norm)
    return false;
  *H = result / norm;
  return true;
}

// The DLT on correspondences already normalised: h the least-squares null vector of the rows.
bool NormalizedDLT(const NormalizedCorrespondences& n, Eigen::Matrix3d* H) {
  const auto rows = [&n](size_t i, const auto& add) {
    Eigen::Matrix<double, 9, 1> a, b;
    DltRows(n, i, &a, &b);
    add(a);
    add(b);
  };
  Eigen::Matrix<double, 9, 1> h;
  if (!NullVectorOfRows<9>(n.x1.size(), rows, &h)) return false;
  return Denormalize(n, MatrixFromRowMajor(h), H);
}

}  // namespace

bool HomographyDLT(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                   Eigen::Matrix3d* H) {
  if (x1.size() < 4 || x1.size() != x2.size()) return false;
  return NormalizedDLT(NormalizeCorrespondences(x1, x2), H);
}

bool Homography4pt(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                   Eigen::Matrix3d* H) {
  if (x1.size() != 4 || x2.size() != 4) return false;
  const NormalizedCorrespondences n = NormalizeCorrespondences(x1, x2);
  // Three collinear points in either image leave the homography undetermined (H&Z section 4.1).
  // Normalised points lie about sqrt(2) from their centroid, so the test is scale-free.
  for (const auto* points : {&n.x1, &n.x2}) {
    for (int skip = 0; skip < 4; ++skip) {
      std::array<Eigen::Vector2d, 3> t;
      for (int i = 0, k = 0; i < 4; ++i)
        if (i != skip) t[k++] = (*points)[i];
      const Eigen::Vector2d u = t[1] - t[0], v = t[2] - t[0];
      if (std::abs(u.x() * v.y() - u.y() * v.x()) < 1e-8) return false;
    }
  }
  Eigen::Matrix<double, 8, 9> A;
  for (size_t i = 0; i < 4; ++i) {
    Eigen::Matrix<double, 9, 1> a, b;
    DltRows(n, i, &a, &b);
    A.row(2 * i) = a.transpose();
    A.row(2 * i + 1) = b.transpose();
  }
  // A [h; 1] = 0 with h the first eight entries: A_8 h = -a_9.
  const Eigen::PartialPivLU<Eigen::Matrix<double, 8, 8>> lu(A.leftCols<8>());
  const double det = lu.determinant();
  // Relative to the scale of the rows (normalised coordinates are O(1), products O(1) too).
  if (!(std::abs(det) > 1e-10) || !std::isfinite(det)) return NormalizedDLT(n, H);
  Eigen::Matrix<double, 9, 1> h;
  h.head<8>() = lu.solve(-A.col(8));
  h[8] = 1;
  if (!h.allFinite()) return false;
  return Denormalize(n, MatrixFromRowMajor(h), H);
}

}  // namespace varsfm
