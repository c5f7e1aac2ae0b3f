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

template <TwoViewModel kModel>
void TwoViewEstimator<kModel>::MinimalSolve(const std::vector<int>& sample,
                                            std::vector<Model>* models) const {
  if constexpr (kModel == TwoViewModel::kHomography) {
    NonMinimalSolve(sample, Model::Zero(), models);  // the four-point DLT is the linear solver
  } else {
    std::vector<Eigen::Vector2d> y1, y2;
    Gather(x1, x2, sample, &y1, &y2);
    if constexpr (kModel == TwoViewModel::kFundamental) {
      Fundamental7pt(y1, y2, models);
    } else {
      Essential5pt(y1, y2, models);
    }
  }
}

template <TwoViewModel kModel>
void TwoViewEstimator<kModel>::NonMinimalSolve(const std::vector<int>& indices,
                                               const Model& /*initial*/,
                                               std::vector<Model>* models) const {
  // E's linear solver is the eight-point one; LO is skipped below eight correspondences.
  if (kModel == TwoViewModel::kEssential && indices.size() < 8) return;
  std::vector<Eigen::Vector2d> y1, y2;
  Gather(x1, x2, indices, &y1, &y2);
  Eigen::Matrix3d M;
  if constexpr (kModel == TwoViewModel::kHomography) {
    if (HomographyDLT(y1, y2, &M)) models->push_back(M);
  } else if (Fundamental8pt(y1, y2, &M)) {
    models->push_back(kModel == TwoViewModel::kEssential ? ProjectToEssential(M) : M);
  }
}

template <TwoViewModel kModel>
double TwoViewEstimator<kModel>::SquaredResidual(const Model& model, size_t i) const {
  if constexpr (kModel == TwoViewModel::kHomography) {
    const Eigen::Vector3d y = model * x1[i].homogeneous();
    if (y.z() == 0) return std::numeric_limits<double>::infinity();
    return (y.hnormalized() - x2[i]).squaredNorm();
  } else {
    return SampsonErrorSquared(model, x1[i], x2[i]);
  }
}

template struct TwoViewEstimator<TwoViewModel::kFundamental>;
template struct TwoViewEstimator<TwoViewModel::kHomography>;
template struct TwoViewEstimator<TwoViewModel::kEssential>;

RansacReport<Eigen::Matrix3d> EstimateFundamentalMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                        const std::vector<Eigen::Vector2d>& x2,
                                                        const RansacOptions& options,
                                                        const NeighbourhoodGraph* neighbourhood) {
  if (x1.size() != x2.size()) return {};
  return Ransac(FundamentalEstimator{x1, x2}, options, neighbourhood);
}

RansacReport<Eigen::Matrix3d> EstimateHomography(const std::vector<Eigen::Vector2d>& x1,
                                                 const std::vector<Eigen::Vector2d>& x2,
                                                 const RansacOptions& options,
                                                 const NeighbourhoodGraph* neighbourhood) {
  if (x1.size() != x2.size()) return {};
  return Ransac(HomographyEstimator{x1, x2}, options, neighbourhood);
}

RansacReport<Eigen::Matrix3d> EstimateEssentialMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                      const std::vector<Eigen::Vector2d>& x2,
                                                      const RansacOptions& options) {
  if (x1.size() != x2.size()) return {};
  return Ransac(EssentialEstimator{x1, x2}, options);
}

}  // namespace varsfm
