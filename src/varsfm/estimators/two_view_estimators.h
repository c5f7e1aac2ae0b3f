#pragma once
// Robust two-view estimation: LO-RANSAC (ransac.h) around the minimal and linear solvers.
//   F: seven-point minimal, normalised eight-point for local optimisation; residual = Sampson
//      distance in pixels; DEGENSAC's plane and parallax when RansacOptions asks for it.
//   H: four-point normalised DLT; residual = one-sided transfer error |x2 - H x1| in pixels
//      (as COLMAP: cheaper than the symmetric error, and the match direction is fixed).
//   E: five-point minimal on normalised coordinates, eight-point + projection onto the
//      essential manifold for local optimisation; residual = Sampson distance in normalised
//      units (max_error in normalised units, e.g. Camera::ImageToNormalizedThreshold).
#include <vector>

#include <Eigen/Core>

#include "varsfm/estimators/ransac.h"

namespace varsfm {

enum class TwoViewModel { kFundamental, kHomography, kEssential };

// Estimator adaptor for Ransac<> of one two-view model (the header says which solvers and
// residual each uses). It keeps references to the data: x1[i] <-> x2[i], pixels for F and H,
// normalised coordinates for E. Defined for the three models in two_view_estimators.cc.
template <TwoViewModel kModel>
struct TwoViewEstimator {
  using Model = Eigen::Matrix3d;
  static constexpr int kMinSampleSize = kModel == TwoViewModel::kFundamental  ? 7
                                        : kModel == TwoViewModel::kHomography ? 4
                                                                              : 5;
  const std::vector<Eigen::Vector2d>& x1;
  const std::vector<Eigen::Vector2d>& x2;
  size_t NumData() const { return x1.size(); }
  void MinimalSolve(const std::vector<int>& sample, std::vector<Model>* models) const;
  void NonMinimalSolve(const std::vector<int>& indices, const Model& initial,
                       std::vector<Model>* models) const;
  double SquaredResidual(const Model& model, size_t i) const;
  // DEGENSAC, F only (fundamental_degeneracy.h): when five of the seven-point `sample` that gave
  // `model` lie on one plane, the best plane-and-parallax F over pairs of data off that plane
  // (MSAC or inlier score as options say; the pairs drawn from `rng`).
  void DegeneracyModels(const std::vector<int>& sample, const Model& model,
                        const RansacOptions& options, Rng* rng, std::vector<Model>* models) const
      requires(kModel == TwoViewModel::kFundamental);
};

using FundamentalEstimator = TwoViewEstimator<TwoViewModel::kFundamental>;
using HomographyEstimator = TwoViewEstimator<TwoViewModel::kHomography>;
using EssentialEstimator = TwoViewEstimator<TwoViewModel::kEssential>;

// `neighbourhood`: graph-cut local optimisation over it (RansacOptions::spatial_coherence).
RansacReport<Eigen::Matrix3d> EstimateFundamentalMatrix(
    const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
    const RansacOptions& options, const NeighbourhoodGraph* neighbourhood = nullptr);

RansacReport<Eigen::Matrix3d> EstimateHomography(const std::vector<Eigen::Vector2d>& x1,
                                                 const std::vector<Eigen::Vector2d>& x2,
                                                 const RansacOptions& options,
                                                 const NeighbourhoodGraph* neighbourhood = nullptr);

// x1, x2 normalised image coordinates; options.max_error in normalised units.
RansacReport<Eigen::Matrix3d> EstimateEssentialMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                      const std::vector<Eigen::Vector2d>& x2,
                                                      const RansacOptions& options);

}  // namespace varsfm
