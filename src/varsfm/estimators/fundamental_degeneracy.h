#pragma once
// DEGENSAC (Chum, Werner & Matas, "Two-view geometry estimation unaffected by a dominant plane",
// CVPR 2005). A seven-point sample of which five correspondences come from one scene plane fixes
// F only up to a one-parameter family that every point of the plane satisfies; the member that
// gathers the most support takes in wrong off-plane matches along its epipolar lines (a facade
// seen by a wide pair). The test finds such samples: a homography compatible with F through
// three of the sample's correspondences that carries five or more of the seven. F is then
// recovered by plane and parallax: the plane's homography and two correspondences off it.
#include <vector>

#include <Eigen/Core>

namespace varsfm {

// The homography induced by the plane through the scene points of three correspondences and
// compatible with F (x2^T F x1 = 0), e2 the epipole in image 2 (F^T e2 = 0): H&Z result 13.6,
// H = A - e2 (M^-1 b)^T with A = [e2]x F, the rows of M the x1_i, and
// b_i = (x2_i x A x1_i)^T (x2_i x e2) / |x2_i x e2|^2. False when M is singular (the three
// collinear in image 1) or a point of image 2 lies on the epipole.
bool HomographyFromFundamental(const Eigen::Matrix3d& F, const Eigen::Vector3d& e2,
                               const Eigen::Vector2d x1[3], const Eigen::Vector2d x2[3],
                               Eigen::Matrix3d* H);

// The DEGENSAC test of a seven-point sample (x1[i] <-> x2[i], i < 7) and an F it gave: true,
// with the plane's homography, when the homography of one of the five triplets of Chum et al.
// (sec. 3: {1,2,3}, {4,5,6}, {1,2,7}, {4,5,7}, {3,6,7}) carries five or more of the seven within
// the squared transfer error threshold2 (|x2 - H x1|^2, pixels^2).
bool FindDominantPlane(const Eigen::Matrix3d& F, const std::vector<Eigen::Vector2d>& x1,
                       const std::vector<Eigen::Vector2d>& x2, double threshold2,
                       Eigen::Matrix3d* H);

// Plane and parallax (H&Z section 13.3): F = [e2]x H, the epipole e2 the intersection of the
// parallax lines (H a1) x a2 and (H b1) x b2 of two correspondences off the plane. False when
// the lines coincide (a correspondence on the plane, or both on one epipolar line).
bool FundamentalFromPlaneAndParallax(const Eigen::Matrix3d& H, const Eigen::Vector2d& a1,
                                     const Eigen::Vector2d& a2, const Eigen::Vector2d& b1,
                                     const Eigen::Vector2d& b2, Eigen::Matrix3d* F);

}  // namespace varsfm
