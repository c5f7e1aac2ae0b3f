#pragma once
// Fundamental-matrix geometry (Hartley & Zisserman, chapter 9): x2^T F x1 = 0 for pixels
// x1 in image 1 and x2 in image 2.
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "varsfm/geometry/rigid3.h"
#include "varsfm/util/types.h"

namespace varsfm {

// The skew-symmetric matrix [v]_x with [v]_x w = v x w.
Eigen::Matrix3d CrossProductMatrix(const Eigen::Vector3d& v);

// Epipoles as unit homogeneous vectors: F e1 = 0 (in image 1), F^T e2 = 0 (in image 2).
void Epipoles(const Eigen::Matrix3d& F, Eigen::Vector3d* e1, Eigen::Vector3d* e2);

// The oriented epipolar constraint (Chum, Werner & Matas, "Epipolar geometry estimation via
// RANSAC benefits from the oriented epipolar constraint", ICPR 2004): for points in front of both
// cameras, the epipolar line F x1 and the line e2 x x2 through the epipole are the same line with
// the same orientation, up to one sign common to every correspondence (F and e2 are known up to
// sign). True when the correspondences x1[i] <-> x2[i] agree on that sign (a correspondence on
// which the sign is 0 agrees with any); an F that fails it cannot come from cameras that see
// those points in front of them.
bool SatisfiesOrientedEpipolarConstraint(const Eigen::Matrix3d& F,
                                         const std::vector<Eigen::Vector2d>& x1,
                                         const std::vector<Eigen::Vector2d>& x2);

// The camera centre C of P (P C = 0) as a homogeneous 4-vector, by cofactor expansion
// (H&Z section 6.2.4: C = (det[p2,p3,p4], -det[p1,p3,p4], det[p1,p2,p4], -det[p1,p2,p3])).
Eigen::Vector4d ProjectionCenter(const Matrix34d& P);

// F = [e2]_x P2 P1^+ with e2 = P2 C1 (H&Z eq. 9.1). Normalised to unit Frobenius norm.
Eigen::Matrix3d FundamentalFromProjections(const Matrix34d& P1, const Matrix34d& P2);

// E = [t]_x R for x_cam2 = R x_cam1 + t (H&Z eq. 9.8).
Eigen::Matrix3d EssentialFromPose(const Rigid3d& cam2_from_cam1);

// F = K2^-T [t]_x R K1^-1 (H&Z eq. 9.12). Normalised to unit Frobenius norm.
Eigen::Matrix3d FundamentalFromPose(const Eigen::Matrix3d& K1, const Eigen::Matrix3d& K2,
                                    const Rigid3d& cam2_from_cam1);

// The squared Sampson distance (H&Z eq. 11.9), the first-order approximation of the squared
// geometric (reprojection) error, in squared pixels for pixel inputs.
// Written out in scalars: RANSAC evaluates it for every datum of every hypothesis, and GCC left
// the Eigen form (F * x1.homogeneous(), ...) as out-of-line calls; the sums are the same, in the
// same order, so the result is the same to the bit.
inline double SampsonErrorSquared(const Eigen::Matrix3d& F, const Eigen::Vector2d& x1,
                                  const Eigen::Vector2d& x2) {
  const double u1 = x1.x(), v1 = x1.y(), u2 = x2.x(), v2 = x2.y();
  // F x1 and the first two entries of F^T x2.
  const double l0 = F(0, 0) * u1 + F(0, 1) * v1 + F(0, 2);
  const double l1 = F(1, 0) * u1 + F(1, 1) * v1 + F(1, 2);
  const double l2 = F(2, 0) * u1 + F(2, 1) * v1 + F(2, 2);
  const double m0 = F(0, 0) * u2 + F(1, 0) * v2 + F(2, 0);
  const double m1 = F(0, 1) * u2 + F(1, 1) * v2 + F(2, 1);
  const double e = u2 * l0 + v2 * l1 + l2;  // x2^T F x1
  const double d = (l0 * l0 + l1 * l1) + (m0 * m0 + m1 * m1);
  return d > 0 ? e * e / d : (e == 0 ? 0.0 : std::numeric_limits<double>::infinity());
}

// The Sampson distance (pixels for pixel inputs).
double SampsonError(const Eigen::Matrix3d& F, const Eigen::Vector2d& x1, const Eigen::Vector2d& x2);

}  // namespace varsfm
