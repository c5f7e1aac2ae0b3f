#pragma once
// The seven-point fundamental-matrix solver (H&Z section 11.1.2): the 2-D null space
// F = a F1 + (1 - a) F2 of the epipolar constraints, with det(F) = 0 a cubic in a.
#include <vector>

#include <Eigen/Core>

namespace varsfm {

// Up to three fundamental matrices (unit Frobenius norm) from the first seven correspondences
// x2^T F x1 = 0. Appends to `models` and returns how many it added.
int Fundamental7pt(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                   std::vector<Eigen::Matrix3d>* models);

}  // namespace varsfm
