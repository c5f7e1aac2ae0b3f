#pragma once
// Non-linear refinement of a fundamental matrix: minimises the sum of squared Sampson
// distances (H&Z section 11.4.3) over a minimal 7-parameter, always-rank-2 parameterisation
// F = U diag(1, s, 0) V^T with U, V rotations (Bartoli & Sturm, "Nonlinear estimation of the
// fundamental matrix with minimal parameters", PAMI 2004, the "orthonormal representation").
#include <vector>

#include <Eigen/Core>

namespace varsfm {

struct FundamentalRefinementOptions {
  int max_iterations = 50;
  // Huber loss scale in pixels (<= 0: plain least squares, for inliers only).
  double huber_scale = 0.0;
};

// Returns the refined F (unit Frobenius norm, rank 2); F itself if the solver fails. Pass
// the inlier correspondences (pixels).
Eigen::Matrix3d RefineFundamentalMatrix(const std::vector<Eigen::Vector2d>& x1,
                                        const std::vector<Eigen::Vector2d>& x2,
                                        const Eigen::Matrix3d& F,
                                        const FundamentalRefinementOptions& options = {});

}  // namespace varsfm
