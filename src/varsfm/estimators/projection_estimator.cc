#include "varsfm/estimators/projection_estimator.h"

#include "varsfm/estimators/projection_dlt.h"
#include "varsfm/estimators/reprojection_residual.h"

namespace varsfm {

void ProjectionEstimator::MinimalSolve(const std::vector<int>& sample,
                                       std::vector<Model>* models) const {
  NonMinimalSolve(sample, Model{}, models);
}

void ProjectionEstimator::NonMinimalSolve(const std::vector<int>& indices, const Model& /*initial*/,
                                          std::vector<Model>* models) const {
  std::vector<Eigen::Vector2d> x(indices.size());
  std::vector<Eigen::Vector3d> X(indices.size());
  for (size_t k = 0; k < indices.size(); ++k) {
    x[k] = points2D[indices[k]];
    X[k] = points3D[indices[k]];
  }
  Matrix34d P;
  if (ProjectionDLT(x, X, &P)) models->push_back(P);
}

double ProjectionEstimator::SquaredResidual(const Model& P, size_t i) const {
  // ProjectionDLT fixes det(M) > 0, so the third coordinate is the depth (H&Z eq. 6.15).
  return SquaredReprojectionResidual(P * points3D[i].homogeneous(), points2D[i]);
}

RansacReport<Matrix34d> EstimateProjectionMatrix(const std::vector<Eigen::Vector2d>& points2D,
                                                 const std::vector<Eigen::Vector3d>& points3D,
                                                 const RansacOptions& options) {
  if (points2D.size() != points3D.size()) return {};
  return Ransac(ProjectionEstimator{points2D, points3D}, options);
}

}  // namespace varsfm
