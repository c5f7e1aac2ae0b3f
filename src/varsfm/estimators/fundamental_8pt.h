#pragma once
// The normalised eight-point algorithm (Hartley 1997; H&Z algorithm 11.1): linear least
// squares on Hartley-normalised points, then the closest rank-2 matrix (Frobenius norm).
#include <vector>

#include <Eigen/Core>

namespace varsfm {

// F (unit Frobenius norm, rank 2) from >= 8 correspondences x2^T F x1 = 0. Returns false for
// fewer points or a degenerate configuration.
bool Fundamental8pt(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                    Eigen::Matrix3d* F);

}  // namespace varsfm
