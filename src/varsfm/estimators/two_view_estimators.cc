#include "varsfm/estimators/two_view_estimators.h"

#include <limits>

#include <Eigen/Geometry>

#include "varsfm/estimators/essential_5pt.h"
#include "varsfm/estimators/fundamental_7pt.h"
#include "varsfm/estimators/fundamental_8pt.h"
#include "varsfm/estimators/homography_4pt.h"
#include "varsfm/geometry/essential.h"
#include "varsfm/geometry/fundamental.h"

namespace varsfm {
namespace {

void Gather(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
            const std::vector<int>& indices, std::vector<Eigen::Vector2d>* y1,
            std::vector<Eigen::Vector2d>* y2) {
  y1->resize(indices.size());
  y2->resize(indices.size());
  for (size_t k = 0; k < indices.size(); ++k) {
    (*y1)[k] = x1[indices[k]];
    (*y2)[k] = x2[indices[k]];
  }
}

}  // namespace

void FundamentalEstimator::MinimalSolve(const std::vector<int>& sample,
                                        std::vector<Model>* models) const {
  std::vector<Eigen::Vector2d> y1, y2;
  Gather(x1, x2, sample, &y1, &y2);
  Fundamental7pt(y1, y2, models);
}

void FundamentalEstimator::NonMinimalSolve(const std::vector<int>& indices,
                                           const Model& /*initial*/,
                                           std::vector<Model>* models) const {
  std::vector<Eigen::Vector2d> y1, y2;
  Gather(x1, x2, indices, &y1, &y2);
  Eigen::Matrix3d F;
  if (Fundamental8pt(y1, y2, &F)) models->push_back(F);
}

double FundamentalEstimator::SquaredResidual(const Model& F, size_t i) const {
  return SampsonErrorSquared(F, x1[i], x2[i]);
}

void HomographyEstimator::MinimalSolve(const std::vector<int>& sample,
                                       std::vector<Model>* models) const {
  NonMinimalSolve(sample, Model{}, models);
}

void HomographyEstimator::NonMinimalSolve(const std::vector<int>& indices, const Model& /*initial*/,
                                          std::vector<Model>* models) const {
  std::vector<Eigen::Vector2d> y1, y2;
  Gather(x1, x2, indices, &y1, &y2);
  Eigen::Matrix3d H;
  if (HomographyDLT(y1, y2, &H)) models->push_back(H);
}

double HomographyEstimator::SquaredResidual(const Model& H, size_t i) const {
  const Eigen::Vector3d y = H * x1[i].homogeneous();
  if (y.z() == 0) return std::numeric_limits<double>::infinity();
  return (y.hnormalized() - x2[i]).squaredNorm();
}

void EssentialEstimator::MinimalSolve(const std::vector<int>& sample,
                                      std::vector<Model>* models) const {
  std::vector<Eigen::Vector2d> y1, y2;
  Gather(x1, x2, sample, &y1, &y2);
  Essential5pt(y1, y2, models);
}

void EssentialEstimator::NonMinimalSolve(const std::vector<int>& indices, const Model& /*initial*/,
                                         std::vector<Model>* models) const {
  if (indices.size() < 8) return;  // the linear solver needs eight; LO is skipped below that
  std::vector<Eigen::Vector2d> y1, y2;
  Gather(x1, x2, indices, &y1, &y2);
  Eigen::Matrix3d F;
  if (Fundamental8pt(y1, y2, &F)) models->push_back(ProjectToEssential(F));
}

double EssentialEstimator::SquaredResidual(const Model& E, size_t i) const {
  return SampsonErrorSquared(E, x1[i], x2[i]);
}

RansacReport<Eigen::Matrix3d> EstimateFundamentalMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                        const std::vector<Eigen::Vector2d>& x2,
                                                        const RansacOptions& options) {
  if (x1.size() != x2.size()) return {};
  return Ransac(FundamentalEstimator{x1, x2}, options);
}

RansacReport<Eigen::Matrix3d> EstimateHomography(const std::vector<Eigen::Vector2d>& x1,
                                                 const std::vector<Eigen::Vector2d>& x2,
                                                 const RansacOptions& options) {
  if (x1.size() != x2.size()) return {};
  return Ransac(HomographyEstimator{x1, x2}, options);
}

RansacReport<Eigen::Matrix3d> EstimateEssentialMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                      const std::vector<Eigen::Vector2d>& x2,
                                                      const RansacOptions& options) {
  if (x1.size() != x2.size()) return {};
  return Ransac(EssentialEstimator{x1, x2}, options);
}

}  // namespace varsfm
