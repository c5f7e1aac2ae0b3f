#pragma once
// Robust camera resection (paper section 4.3): LO-RANSAC around the six-point normalised DLT
// for P = K [R | t] from 2D-3D matches. Residual = pixel reprojection error; a point behind the
// camera (non-positive depth for the sign-fixed P, see projection_dlt.h) is an outlier.
#include <vector>

#include <Eigen/Core>

#include "varsfm/estimators/ransac.h"
#include "varsfm/util/types.h"

namespace varsfm {

struct ProjectionEstimator {
  using Model = Matrix34d;
  static constexpr int kMinSampleSize = 6;
  const std::vector<Eigen::Vector2d>& points2D;
  const std::vector<Eigen::Vector3d>& points3D;
  size_t NumData() const { return points2D.size(); }
  void MinimalSolve(const std::vector<int>& sample, std::vector<Model>* models) const;
  void NonMinimalSolve(const std::vector<int>& indices, const Model& initial,
                       std::vector<Model>* models) const;
  double SquaredResidual(const Model& P, size_t i) const;
};

RansacReport<Matrix34d> EstimateProjectionMatrix(const std::vector<Eigen::Vector2d>& points2D,
                                                 const std::vector<Eigen::Vector3d>& points3D,
                                                 const RansacOptions& options);

}  // namespace varsfm
