#include "varsfm/sfm/absolute_pose_refinement.h"

#include <ceres/ceres.h>

#include "varsfm/ba/analytic_reprojection_cost.h"

namespace varsfm {

bool RefineAbsolutePose(const AbsolutePoseRefinementOptions& options,
                        const std::vector<Eigen::Vector2d>& points2D,
                        const std::vector<Eigen::Vector3d>& points3D, Camera* camera,
                        Rigid3d* cam_from_world) {
  if (points2D.size() != points3D.size() || points2D.size() < 6) return false;
  std::vector<Eigen::Vector3d> points = points3D;  // Ceres needs mutable blocks, held constant
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::CauchyLoss loss(options.loss_scale_px);
  double* q = cam_from_world->rotation.coeffs().data();
  double* t = cam_from_world->translation.data();
  for (size_t i = 0; i < points.size(); ++i) {
    // The analytic Jacobians (ba/analytic_reprojection_cost.h) of the model the bundle
    // adjustments use: automatic differentiation took half of the refinement's time.
    problem.AddResidualBlock(new AnalyticReprojectionCost(points2D[i]), &loss,
                             camera->params.data(), q, t, points[i].data());
    problem.SetParameterBlockConstant(points[i].data());
  }
  problem.SetManifold(q, new ceres::EigenQuaternionManifold);

  const IntrinsicsOptions& in = options.intrinsics;
  std::vector<int> held;
  if (!in.refine_focal) held.push_back(Camera::kFocal);
  if (!in.refine_aspect) held.push_back(Camera::kAspect);
  if (!in.refine_skew) held.push_back(Camera::kSkew);
  if (!in.refine_principal_point) {
    held.push_back(Camera::kU0);
    held.push_back(Camera::kV0);
  }
  if (!in.refine_k1) held.push_back(Camera::kK1);
  if (!in.refine_k2) held.push_back(Camera::kK2);
  if (held.size() == Camera::kNumParams) {
    problem.SetParameterBlockConstant(camera->params.data());
  } else if (!held.empty()) {
    problem.SetManifold(camera->params.data(), new ceres::SubsetManifold(Camera::kNumParams, held));
  }

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  cam_from_world->rotation.normalize();
  return summary.IsSolutionUsable();
}

}  // namespace varsfm
