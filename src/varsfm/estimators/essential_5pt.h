#pragma once
// The five-point relative-pose solver for calibrated cameras (Nister, "An efficient solution to
// the five-point relative pose problem", PAMI 2004), solved as in Stewenius, Engels & Nister,
// "Recent developments on direct relative orientation" (ISPRS 2006): the essential matrix lies
// in the 4-D null space of the epipolar constraints, E = x X + y Y + z Z + W, and the ten cubic
// constraints det(E) = 0, 2 E E^T E - tr(E E^T) E = 0 are solved with an action matrix
// (Groebner basis) whose eigenvectors give the up to ten real solutions.
#include <vector>

#include <Eigen/Core>

namespace varsfm {

// Essential matrices (unit Frobenius norm) from the first five correspondences in normalised
// image coordinates, x2^T E x1 = 0. Appends to `models` and returns how many it added.
int Essential5pt(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                 std::vector<Eigen::Matrix3d>* models);

}  // namespace varsfm
