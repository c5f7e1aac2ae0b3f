#pragma once
// Closed-form focal lengths of two views from their fundamental matrix when the principal
// points are known, the aspect ratio is 1 and the skew 0 (S. Bougnoux, "From projective to
// Euclidean space under any practical situation, a criticism of self-calibration", ICCV 1998;
// Hartley & Zisserman 2nd ed., exercise in chapter 19). With I~ = diag(1, 1, 0), e2 the
// epipole in image 2 (F^T e2 = 0) and p1, p2 the principal points (homogeneous):
//
//   f1^2 = - (p2^T [e2]x I~ F p1) (p1^T F^T p2) / (p2^T [e2]x I~ F I~ F^T p2)
//
// and f2^2 by the same formula on F^T with the roles of the images swapped. The formula is
// singular when the optical axes are coplanar (p2^T F p1 = 0: the principal points are in
// epipolar correspondence), the classic degenerate configuration of two-view self-calibration.
#include <optional>
#include <utility>

#include <Eigen/Core>

namespace varsfm {

// Squared focal lengths (pixels^2); they may be negative for noisy or degenerate data.
std::pair<double, double> BougnouxSquaredFocalLengths(const Eigen::Matrix3d& F,
                                                      const Eigen::Vector2d& pp1,
                                                      const Eigen::Vector2d& pp2);

// Focal lengths (pixels), or nullopt when either squared focal length is not positive.
std::optional<std::pair<double, double>> BougnouxFocalLengths(const Eigen::Matrix3d& F,
                                                              const Eigen::Vector2d& pp1,
                                                              const Eigen::Vector2d& pp2);

// Distance (pixels) from p2 to the epipolar line of p1: near 0 the optical axes are nearly
// coplanar and Bougnoux's formula is ill-conditioned.
double PrincipalPointEpipolarDistance(const Eigen::Matrix3d& F, const Eigen::Vector2d& pp1,
                                      const Eigen::Vector2d& pp2);

}  // namespace varsfm
