#pragma once
// Calibrated absolute pose from three 2D-3D correspondences: Lambda Twist (Persson & Nordberg,
// "Lambda Twist: An Accurate Fast Robust Perspective Three Point (P3P) Solver", ECCV 2018).
// The three depths lambda_i along the bearings meet the three distance constraints
// |lambda_i y_i - lambda_j y_j|^2 = |X_i - X_j|^2; two homogeneous combinations of them (D1,
// D2) share a degenerate member D0 = D1 + gamma D2 (gamma a real root of a cubic), whose
// factorisation into two planes through the origin gives the depths from one quadratic each;
// a few Gauss-Newton steps on the three constraints polish them (section 3 of the paper).
#include <array>
#include <vector>

#include <Eigen/Core>

#include "varsfm/geometry/rigid3.h"

namespace varsfm {

// The cam_from_world poses (x_cam = R X + t) that put the world points `points` on the rays
// `bearings` (unit vectors in the camera frame, any length > 0 is normalised), in front of the
// camera. Appends up to four poses to `poses` and returns how many; none for a degenerate
// sample (coincident points, parallel bearings).
int SolveP3P(const std::array<Eigen::Vector3d, 3>& bearings,
             const std::array<Eigen::Vector3d, 3>& points, std::vector<Rigid3d>* poses);

}  // namespace varsfm
