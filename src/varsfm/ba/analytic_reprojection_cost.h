#pragma once
// The reprojection residual of eq. (34) (reprojection_cost.h) with hand-derived Jacobians.
// Bundle adjustment spends most of its time evaluating Jacobians, and automatic differentiation
// took most of the solver's time (docs/measurements.md). The functors in reprojection_cost.h
// stay as the reference the tests compare these Jacobians against.
//
// Derivation (camera.h's model; p = R(q) X + t the point in camera coordinates):
//   n = (px / pz, py / pz),  r2 = |n|^2,  d = 1 + k1 r2 + k2 r2^2,  m = d n,
//   u = f mx + s my + u0,  v = e f my + v0.
//   d(u, v)/dm = A = [f s; 0 e f]
//   dm/dn     = B = d I + g n n^T,  g = 2 (k1 + 2 k2 r2)
//   dn/dp     = C = [1/pz 0 -px/pz^2; 0 1/pz -py/pz^2]
//   d/dt = A B C,  d/dX = A B C R,
//   d/dq = A B C dp/dq with, for the unit quaternion q = (v, w) (Eigen's x, y, z, w order),
//   R X = X + 2 w (v x X) + 2 v x (v x X):
//     dp/dv = -2 w [X]x + 2 ((v . X) I + v X^T - 2 X v^T),   dp/dw = 2 v x X.
//   The formula equals R(q) X on the unit sphere only, so its derivative is exact along the
//   sphere's tangent, the only directions Ceres' EigenQuaternionManifold uses.
//   Intrinsics [f, e, s, u0, v0, k1, k2]:
//     du = [mx, 0, my, 1, 0, (f nx + s ny) r2, (f nx + s ny) r2^2]
//     dv = [e my, f my, 0, 0, 1, e f ny r2, e f ny r2^2]
#include <optional>

#include <ceres/cost_function.h>

#include <Eigen/Core>

#include "varsfm/camera/camera.h"

namespace varsfm {

// How the parameters of one residual are grouped into Ceres blocks. Ceres' Schur eliminator
// updates the reduced camera system block pair by block pair, so for a point seen by t images
// the work grows with (t x blocks per image)^2: on a 100-image sequence (tracks of ~17 images)
// the final global adjustment spent 7.7 of 8.5 s there with three blocks per image. One block
// per image makes that count ~9x smaller for the same arithmetic.
//
// The pose blocks hold the camera centre C instead of the translation t = -R C (p = R (X - C)):
// the bending of a long sequence in a global adjustment (images far from the world origin turning
// about a distant pivot) is then much less non-linear than with t, whose change under a rotation
// grows with the distance to the origin.
enum class ReprojectionBlocks {
  // camera [f, e, s, u0, v0, k1, k2] (7), rotation quaternion [x, y, z, w] (4), translation (3)
  kCameraRotationTranslation,
  // camera (7), pose [quaternion (4), centre (3)] (7): a camera several images share
  kCameraPose,
  // image [camera (7), quaternion (4), centre (3)] (14): a camera of its own
  kImage,
};

// The blocks, in order: those of `blocks`, then the point (3). With a shared block, it follows
// the camera (or the image block): the per-size block (7) that parameter i comes from when bit i
// of its mask is set (reprojection_cost.h); the camera's own column is then zero, and the other
// way round.
class AnalyticReprojectionCost final : public ceres::CostFunction {
 public:
  explicit AnalyticReprojectionCost(
      const Eigen::Vector2d& observed,
      ReprojectionBlocks blocks = ReprojectionBlocks::kCameraRotationTranslation,
      std::optional<unsigned> shared_mask = std::nullopt);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Eigen::Vector2d observed_;
  ReprojectionBlocks blocks_;
  std::optional<unsigned> shared_mask_;
};

}  // namespace varsfm
