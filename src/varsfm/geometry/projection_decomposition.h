#pragma once
// Decomposition of a 3x4 projection matrix P ~ K [R | t] into its calibration and pose
// (Hartley & Zisserman, section 6.2.4): the left 3x3 block M = K R is split by an RQ
// decomposition into an upper-triangular K and an orthonormal R.
#include <Eigen/Core>

#include "varsfm/util/types.h"

namespace varsfm {

// M = K R with K upper triangular with a positive diagonal and R orthonormal (det(R) =
// sign(det(M))). Returns false when M is singular.
bool RQDecomposition(const Eigen::Matrix3d& M, Eigen::Matrix3d* K, Eigen::Matrix3d* R);

// P = lambda K [R | t] with K(2,2) = 1, positive diagonal, det(R) = +1. The overall sign of P
// is free (a homogeneous quantity), so it is chosen to make det(M) > 0, which is what
// det(R) = +1 requires. Returns false when M is singular.
bool DecomposeProjectionMatrix(const Matrix34d& P, Eigen::Matrix3d* K, Eigen::Matrix3d* R,
                               Eigen::Vector3d* t);

}  // namespace varsfm
