#include "varsfm/sfm/absolute_pose_refinement.h"

#include <deque>
#include <memory>

#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include "varsfm/ba/analytic_reprojection_cost.h"
#include "varsfm/ba/schur_solver.h"

namespace varsfm {

bool RefineAbsolutePose(const AbsolutePoseRefinementOptions& options,
                        const std::vector<Eigen::Vector2d>& points2D,
                        const std::vector<Eigen::Vector3d>& points3D, Camera* camera,
                        Rigid3d* cam_from_world) {
  if (points2D.size() != points3D.size() || points2D.size() < 6) return false;
  const std::vector<int> held = HeldIntrinsics(options.intrinsics);
  const bool camera_constant = held.size() == Camera::kNumParams;
  std::unique_ptr<ceres::Manifold> camera_manifold;
  if (!camera_constant && !held.empty())
    camera_manifold = std::make_unique<ceres::SubsetManifold>(Camera::kNumParams, held);
  const ceres::EigenQuaternionManifold rotation_manifold;
  const ceres::CauchyLoss loss(options.loss_scale_px);

  // One image's pose and free intrinsics, the points held: nothing to eliminate, a reduced
  // system of at most 7 + 3 + 3 columns.
  double* q = cam_from_world->rotation.coeffs().data();
  double* t = cam_from_world->translation.data();
  LeastSquaresProblem problem;
  problem.Reserve(3 + points3D.size(), points2D.size(), 4 * points2D.size());
  problem.AddParameterBlock(camera->params.data(), Camera::kNumParams, camera_manifold.get(),
                            camera_constant);
  problem.AddParameterBlock(q, 4, &rotation_manifold);
  problem.AddParameterBlock(t, 3);
  std::deque<AnalyticReprojectionCost> costs;
  for (size_t i = 0; i < points2D.size(); ++i) {
    // The solver never writes a constant block.
    double* point = const_cast<double*>(points3D[i].data());
    problem.AddParameterBlock(point, 3, nullptr, /*constant=*/true);
    costs.emplace_back(points2D[i]);
    const double* blocks[] = {camera->params.data(), q, t, point};
    problem.AddResidualBlock(&costs.back(), &loss, blocks, 4);
  }
  SchurSolverOptions solver;
  solver.max_iterations = options.max_iterations;
  const SchurSolverSummary summary = SolveWithSchurComplement(solver, /*eliminate=*/{}, problem);
  cam_from_world->rotation.normalize();
  return summary.usable;
}

}  // namespace varsfm
