#pragma once
// The reprojection residual of eq. (34) (reprojection_cost.h) with hand-derived Jacobians.
// Bundle adjustment spends most of its time evaluating Jacobians: measured on fountain-P11's
// final global adjustment (51k observations, 11 cameras), automatic differentiation took 60 %
// of the solver's time (0.89 s of 1.48 s). The functors in reprojection_cost.h stay as the
// reference the tests compare these Jacobians against.
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
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "varsfm/camera/camera.h"

namespace varsfm {

// Blocks: camera [f, e, s, u0, v0, k1, k2] (7), rotation quaternion [x, y, z, w] (4),
// translation (3), point (3).
class AnalyticReprojectionCost final
    : public ceres::SizedCostFunction<2, Camera::kNumParams, 4, 3, 3> {
 public:
  explicit AnalyticReprojectionCost(const Eigen::Vector2d& observed) : observed_(observed) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Eigen::Vector2d observed_;
};

// Blocks: camera (7), the per-size shared block (7), rotation, translation, point; parameter i
// comes from the shared block when bit i of `shared_mask` is set (reprojection_cost.h).
class AnalyticSharedIntrinsicsReprojectionCost final
    : public ceres::SizedCostFunction<2, Camera::kNumParams, Camera::kNumParams, 4, 3, 3> {
 public:
  AnalyticSharedIntrinsicsReprojectionCost(const Eigen::Vector2d& observed, unsigned shared_mask)
      : observed_(observed), shared_mask_(shared_mask) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Eigen::Vector2d observed_;
  unsigned shared_mask_;
};

}  // namespace varsfm
