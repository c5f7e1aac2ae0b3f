#pragma once
// The normalised DLT for a plane-induced homography x2 ~ H x1 (H&Z algorithm 4.2): exact from
// four correspondences, algebraic least squares from more.
#include <vector>

#include <Eigen/Core>

namespace varsfm {

// H (unit Frobenius norm) from >= 4 correspondences. Returns false when degenerate.
bool HomographyDLT(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                   Eigen::Matrix3d* H);

}  // namespace varsfm
