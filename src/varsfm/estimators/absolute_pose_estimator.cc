#include "varsfm/estimators/absolute_pose_estimator.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "varsfm/estimators/p3p.h"
#include "varsfm/estimators/reprojection_residual.h"

namespace varsfm {
namespace {

// Cost of a point behind the camera in the refinement: far above any squared inlier residual
// in normalised units, so that no accepted step moves an inlier behind the camera.
constexpr double kBehindCameraCost = 1.0;

// Sum of squared reprojection errors of `indices` under `pose`.
double ReprojectionCost(const AbsolutePoseEstimator& e, const std::vector<int>& indices,
                        const Rigid3d& pose) {
  double cost = 0;
  for (const int i : indices) {
    const Eigen::Vector3d p = pose * e.points3D[i];
    cost += p.z() > 0 ? (p.hnormalized() - e.points2D[i]).squaredNorm() : kBehindCameraCost;
  }
  return cost;
}

// Normal equations J^T J, J^T r of the reprojection errors for the update
// R <- exp([omega]x) R, t <- t + delta_t (parameters omega, delta_t).
void NormalEquations(const AbsolutePoseEstimator& e, const std::vector<int>& indices,
                     const Rigid3d& pose, Eigen::Matrix<double, 6, 6>* H,
                     Eigen::Matrix<double, 6, 1>* g) {
  H->setZero();
  g->setZero();
  for (const int i : indices) {
    const Eigen::Vector3d rotated = pose.rotation * e.points3D[i];
    const Eigen::Vector3d p = rotated + pose.translation;
    if (!(p.z() > 0)) continue;
    const double inv_z = 1.0 / p.z();
    const Eigen::Vector2d r = p.hnormalized() - e.points2D[i];
    Eigen::Matrix<double, 2, 3> d_projection;
    d_projection << inv_z, 0, -p.x() * inv_z * inv_z, 0, inv_z, -p.y() * inv_z * inv_z;
    Eigen::Matrix3d skew;  // d p / d omega = -[R X]x
    skew << 0, rotated.z(), -rotated.y(), -rotated.z(), 0, rotated.x(), rotated.y(), -rotated.x(),
        0;
    Eigen::Matrix<double, 2, 6> J;
    J << d_projection * skew, d_projection;
    H->noalias() += J.transpose() * J;
    g->noalias() += J.transpose() * r;
  }
}

Rigid3d Update(const Rigid3d& pose, const Eigen::Matrix<double, 6, 1>& step) {
  const Eigen::Vector3d omega = step.head<3>();
  const double angle = omega.norm();
  const Eigen::Quaterniond dq = angle > 0
                                    ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, omega / angle))
                                    : Eigen::Quaterniond::Identity();
  return {(dq * pose.rotation).normalized(), pose.translation + step.tail<3>()};
}

// One Levenberg-Marquardt step: raises the damping until a step lowers the cost, or fails.
bool DampedStep(const AbsolutePoseEstimator& e, const std::vector<int>& indices, Rigid3d* pose,
                double* cost, double* damping) {
  Eigen::Matrix<double, 6, 6> H;
  Eigen::Matrix<double, 6, 1> g;
  NormalEquations(e, indices, *pose, &H, &g);
  for (; *damping < 1e8; *damping *= 10) {
    Eigen::Matrix<double, 6, 6> A = H;
    A.diagonal() += *damping * H.diagonal() + Eigen::Matrix<double, 6, 1>::Constant(1e-12);
    const Rigid3d candidate = Update(*pose, -A.ldlt().solve(g));
    const double candidate_cost = ReprojectionCost(e, indices, candidate);
    if (candidate_cost < *cost) {
      *pose = candidate;
      *cost = candidate_cost;
      *damping = std::max(*damping * 0.1, 1e-10);
      return true;
    }
  }
  return false;
}

}  // namespace

void AbsolutePoseEstimator::MinimalSolve(const std::vector<int>& sample,
                                         std::vector<Model>* models) const {
  std::array<Eigen::Vector3d, 3> bearings, points;
  for (int k = 0; k < 3; ++k) {
    bearings[k] = points2D[sample[k]].homogeneous();
    points[k] = points3D[sample[k]];
  }
  SolveP3P(bearings, points, models);
}

void AbsolutePoseEstimator::NonMinimalSolve(const std::vector<int>& indices, const Model& initial,
                                            std::vector<Model>* models) const {
  // Six unknowns need at least three points (two equations each).
  if (indices.size() < 3) return;
  constexpr int kMaxIterations = 20;
  Rigid3d pose = initial;
  double cost = ReprojectionCost(*this, indices, pose);
  double damping = 1e-4;  // Levenberg-Marquardt, relative to the diagonal of J^T J
  for (int iteration = 0; iteration < kMaxIterations && cost > 0; ++iteration) {
    const double previous = cost;
    if (!DampedStep(*this, indices, &pose, &cost, &damping)) break;
    if (previous - cost < 1e-10 * previous) break;
  }
  models->push_back(pose);
}

double AbsolutePoseEstimator::SquaredResidual(const Model& pose, size_t i) const {
  return SquaredReprojectionResidual(pose * points3D[i], points2D[i]);
}

}  // namespace varsfm
