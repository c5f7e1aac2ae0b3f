#include "varsfm/estimators/fundamental_refinement.h"

#include <cmath>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <Eigen/SVD>

namespace varsfm {
namespace {

// F(params) = R(wu) U0 diag(1, s, 0) V0^T R(wv)^T; the rotation updates wu, wv (angle-axis)
// start at zero, so the parameterisation is centred on the initial estimate.
template <typename T>
Eigen::Matrix<T, 3, 3> ComposeF(const Eigen::Matrix3d& U0, const Eigen::Matrix3d& V0, const T* wu,
                                const T* wv, const T* s) {
  Eigen::Matrix<T, 3, 3> Ru, Rv;
  ceres::AngleAxisToRotationMatrix(wu, ceres::ColumnMajorAdapter3x3(Ru.data()));
  ceres::AngleAxisToRotationMatrix(wv, ceres::ColumnMajorAdapter3x3(Rv.data()));
  const Eigen::Matrix<T, 3, 3> U = Ru * U0.cast<T>();
  const Eigen::Matrix<T, 3, 3> V = Rv * V0.cast<T>();
  Eigen::Matrix<T, 3, 3> D = Eigen::Matrix<T, 3, 3>::Zero();
  D(0, 0) = T(1);
  D(1, 1) = s[0];
  return U * D * V.transpose();
}

// Signed Sampson distance of one correspondence (its square is H&Z eq. 11.9).
struct SampsonCost {
  SampsonCost(const Eigen::Vector2d& x1, const Eigen::Vector2d& x2, const Eigen::Matrix3d& U0,
              const Eigen::Matrix3d& V0)
      : x1(x1), x2(x2), U0(U0), V0(V0) {}

  template <typename T>
  bool operator()(const T* wu, const T* wv, const T* s, T* residual) const {
    const Eigen::Matrix<T, 3, 3> F = ComposeF(U0, V0, wu, wv, s);
    const Eigen::Matrix<T, 3, 1> p1 = x1.homogeneous().cast<T>();
    const Eigen::Matrix<T, 3, 1> p2 = x2.homogeneous().cast<T>();
    const Eigen::Matrix<T, 3, 1> Fx1 = F * p1;
    const Eigen::Matrix<T, 3, 1> Ftx2 = F.transpose() * p2;
    const T d = Fx1(0) * Fx1(0) + Fx1(1) * Fx1(1) + Ftx2(0) * Ftx2(0) + Ftx2(1) * Ftx2(1);
    residual[0] = p2.dot(Fx1) / ceres::sqrt(d + T(1e-300));
    return true;
  }

  Eigen::Vector2d x1, x2;
  Eigen::Matrix3d U0, V0;
};

}  // namespace

Eigen::Matrix3d RefineFundamentalMatrix(const std::vector<Eigen::Vector2d>& x1,
                                        const std::vector<Eigen::Vector2d>& x2,
                                        const Eigen::Matrix3d& F,
                                        const FundamentalRefinementOptions& options) {
  if (x1.size() != x2.size() || x1.size() < 8) return F;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d sigma = svd.singularValues();
  if (!(sigma[0] > 0)) return F;
  // Scale is free, so sigma1 is fixed to 1 and only s = sigma2 / sigma1 is estimated.
  const Eigen::Matrix3d U0 = svd.matrixU(), V0 = svd.matrixV();
  double wu[3] = {0, 0, 0}, wv[3] = {0, 0, 0}, s = sigma[1] / sigma[0];

  ceres::Problem problem;
  for (size_t i = 0; i < x1.size(); ++i) {
    ceres::LossFunction* loss =
        options.huber_scale > 0 ? new ceres::HuberLoss(options.huber_scale) : nullptr;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SampsonCost, 1, 3, 3, 1>(
                                 new SampsonCost(x1[i], x2[i], U0, V0)),
                             loss, wu, wv, &s);
  }
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (!summary.IsSolutionUsable() || summary.final_cost > summary.initial_cost) return F;
  const Eigen::Matrix3d refined = ComposeF<double>(U0, V0, wu, wv, &s);
  const double norm = refined.norm();
  if (!(norm > 0) || !std::isfinite(norm)) return F;
  // Keep the sign of the input (F and -F are the same model).
  const Eigen::Matrix3d result = refined / norm;
  return result.cwiseProduct(F).sum() < 0 ? Eigen::Matrix3d(-result) : result;
}

}  // namespace varsfm
