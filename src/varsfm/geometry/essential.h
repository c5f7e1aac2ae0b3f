#pragma once
// Essential-matrix geometry (Hartley & Zisserman, section 9.6): E = [t]_x R for normalised
// image coordinates, x2^T E x1 = 0 with x_cam2 = R x_cam1 + t.
#include <vector>

#include <Eigen/Core>

#include "varsfm/geometry/rigid3.h"

namespace varsfm {

// The two rotations and the unit translation of E = U diag(1,1,0) V^T (H&Z result 9.19):
// R1 = U W V^T, R2 = U W^T V^T, t = u3. The four poses are (R1, +-t), (R2, +-t).
void DecomposeEssentialMatrix(const Eigen::Matrix3d& E, Eigen::Matrix3d* R1, Eigen::Matrix3d* R2,
                              Eigen::Vector3d* t);

// The closest essential matrix in Frobenius norm (H&Z result 9.18): singular values
// (s1, s2, s3) -> ((s1 + s2) / 2, (s1 + s2) / 2, 0), scaled to unit Frobenius norm.
Eigen::Matrix3d ProjectToEssential(const Eigen::Matrix3d& M);

// The four candidate cam2_from_cam1 poses of E.
std::vector<Rigid3d> PosesFromEssentialMatrix(const Eigen::Matrix3d& E);

// Chooses among the four poses the one that puts most correspondences in front of both
// cameras (triangulated linearly). Returns that number; `cheirality_mask` (optional) marks the
// correspondences in front of both cameras for the chosen pose. x1, x2 are normalised
// coordinates.
int PoseFromEssentialMatrix(const Eigen::Matrix3d& E, const std::vector<Eigen::Vector2d>& x1,
                            const std::vector<Eigen::Vector2d>& x2, Rigid3d* cam2_from_cam1,
                            std::vector<char>* cheirality_mask = nullptr);

}  // namespace varsfm
