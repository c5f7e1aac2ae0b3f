#pragma once
// The normalised DLT for a plane-induced homography x2 ~ H x1 (H&Z algorithm 4.2): exact from
// four correspondences, algebraic least squares from more.
#include <vector>

#include <Eigen/Core>

namespace varsfm {

// H (unit Frobenius norm) from >= 4 correspondences. Returns false when degenerate.
bool HomographyDLT(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                   Eigen::Matrix3d* H);

// H (unit Frobenius norm) from exactly four correspondences, the minimal solver: the same DLT
// rows, solved as the 8 x 8 linear system with h33 = 1 (after Hartley's normalisation h33 is
// far from 0 unless the centroid of x1 maps to infinity), an LU solve instead of the 9 x 9
// eigen-decomposition. False when degenerate (three of the points collinear in either image);
// HomographyDLT when the 8 x 8 system is nonetheless singular.
bool Homography4pt(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                   Eigen::Matrix3d* H);

}  // namespace varsfm
