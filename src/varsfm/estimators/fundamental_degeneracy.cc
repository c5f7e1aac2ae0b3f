#include "varsfm/estimators/fundamental_degeneracy.h"

#include <cmath>

#include <Eigen/LU>

#include "varsfm/geometry/fundamental.h"

namespace varsfm {

bool HomographyFromFundamental(const Eigen::Matrix3d& F, const Eigen::Vector3d& e2,
                               const Eigen::Vector2d x1[3], const Eigen::Vector2d x2[3],
                               Eigen::Matrix3d* H) {
  const Eigen::Matrix3d A = CrossProductMatrix(e2) * F;
  Eigen::Matrix3d M;
  Eigen::Vector3d b;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d p1 = x1[i].homogeneous(), p2 = x2[i].homogeneous();
    M.row(i) = p1.transpose();
    const Eigen::Vector3d p2_e2 = p2.cross(e2);
    const double norm2 = p2_e2.squaredNorm();
    if (!(norm2 > 0)) return false;
    b[i] = p2.cross(A * p1).dot(p2_e2) / norm2;
  }
  Eigen::FullPivLU<Eigen::Matrix3d> lu(M);
  if (!lu.isInvertible()) return false;
  *H = A - e2 * lu.solve(b).transpose();
  return H->allFinite();
}

bool FindDominantPlane(const Eigen::Matrix3d& F, const std::vector<Eigen::Vector2d>& x1,
                       const std::vector<Eigen::Vector2d>& x2, double threshold2,
                       Eigen::Matrix3d* H) {
  if (x1.size() < 7 || x2.size() < 7) return false;
  Eigen::Vector3d e1, e2;
  Epipoles(F, &e1, &e2);
  static constexpr int kTriplets[5][3] = {{0, 1, 2}, {3, 4, 5}, {0, 1, 6}, {3, 4, 6}, {2, 5, 6}};
  for (const auto& triplet : kTriplets) {
    const Eigen::Vector2d t1[3] = {x1[triplet[0]], x1[triplet[1]], x1[triplet[2]]};
    const Eigen::Vector2d t2[3] = {x2[triplet[0]], x2[triplet[1]], x2[triplet[2]]};
    Eigen::Matrix3d candidate;
    if (!HomographyFromFundamental(F, e2, t1, t2, &candidate)) continue;
    int carried = 0;
    for (int i = 0; i < 7; ++i) {
      const Eigen::Vector3d y = candidate * x1[i].homogeneous();
      if (y.z() != 0 && (y.hnormalized() - x2[i]).squaredNorm() < threshold2) ++carried;
    }
    if (carried >= 5) {
      *H = candidate;
      return true;
    }
  }
  return false;
}

bool FundamentalFromPlaneAndParallax(const Eigen::Matrix3d& H, const Eigen::Vector2d& a1,
                                     const Eigen::Vector2d& a2, const Eigen::Vector2d& b1,
                                     const Eigen::Vector2d& b2, Eigen::Matrix3d* F) {
  // Each line joins x2 and H x1 in image 2; both pass through the epipole.
  const Eigen::Vector3d la = (H * a1.homogeneous()).cross(a2.homogeneous());
  const Eigen::Vector3d lb = (H * b1.homogeneous()).cross(b2.homogeneous());
  const Eigen::Vector3d e2 = la.cross(lb);
  // Parallel lines meet at infinity (a valid epipole); coincident ones give the zero vector.
  if (!(e2.norm() > 1e-12 * la.norm() * lb.norm())) return false;
  *F = CrossProductMatrix(e2) * H;
  const double norm = F->norm();
  if (!(norm > 0) || !std::isfinite(norm)) return false;
  *F /= norm;
  return true;
}

}  // namespace varsfm
