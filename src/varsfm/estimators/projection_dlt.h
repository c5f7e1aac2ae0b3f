#pragma once
// The normalised DLT for a camera projection matrix P from 2D-3D correspondences x ~ P X
// (H&Z algorithm 7.1; paper section 4.3): 11 unknowns, two equations per correspondence, so
// six correspondences give a (slightly over-determined) solution.
#include <vector>

#include <Eigen/Core>

#include "varsfm/util/types.h"

namespace varsfm {

// P from >= 6 correspondences. The scale of P is fixed so that det(P(:, 0:3)) > 0 and the
// third row of its left 3x3 block has unit norm; then P.row(2) (X, 1) is the depth of X
// (H&Z eq. 6.15), positive in front of the camera. Returns false when degenerate.
bool ProjectionDLT(const std::vector<Eigen::Vector2d>& points2D,
                   const std::vector<Eigen::Vector3d>& points3D, Matrix34d* P);

}  // namespace varsfm
